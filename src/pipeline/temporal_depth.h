/* SPDX-License-Identifier: MIT */
/*
 * The temporal depth filter for streams: per pixel an exponential history of
 * 1/z (in the spirit of librealsense's temporal filter), reset where a new
 * sample disagrees with it by more than `reject` times the expected noise
 * (something moved in or out: disocclusion).  Runs on the decoded depth,
 * before the spatial prefilter.
 *
 * Why 1/z: structured-light and stereo sensors measure disparity, which is
 * proportional to 1/z, so their noise is about constant there (sigma(z) =
 * k z^2 in depth is sigma = k in 1/z) and one threshold fits every depth;
 * a plane stays a plane under averaging in 1/z.
 */
#ifndef DAO_PIPELINE_TEMPORAL_DEPTH_H
#define DAO_PIPELINE_TEMPORAL_DEPTH_H

#include <stddef.h>
#include <stdint.h>

/* Largest count of a pixel's history: 1/count is the new sample's weight
 * until 1 - alpha takes over (so the first frames are a plain mean). */
#define DAO_TEMPORAL_DEPTH_MAX_COUNT 255

struct dao_temporal_depth_setup {
	int width;
	float alpha;    /* share of the history in the output, (0, 1) */
	float reject;   /* the history restarts where |1/z - history| > reject sigma */
	float noise_k;  /* sensor model: sigma of 1/z is k (1/m), sigma(z) = k z^2 */
	float quantum;  /* input depth step, m (DEPTH16: its unit), 0 for float input */
	int persist;    /* frames a pixel without data keeps its last value (0 = none) */
	int fresh;      /* 1: no history (first frame, a gap, a seek, a reset) */
	/* per-pixel sigma of 1/z (1/m), e.g. from a noise estimate, or NULL for
	 * the model sqrt(k^2 + quantum^2 / (12 z^4)) (noise plus rounding) */
	const float *sigma;
};

/*
 * Rows [y0, y1) of the depth plane `z` (metres, 0 = no data; width per row,
 * tightly packed) in place, with the per-pixel state: `hist` the filtered
 * 1/z, `count` the samples in it (0 = none), `age` the frames since the
 * pixel last had data.  Where a pixel has data: a first sample or one the
 * test rejects -- |1/z - history| > reject sigma sqrt(1 + v), v the history's
 * own variance in units of sigma^2 (1/count, at least (1 - alpha) /
 * (1 + alpha)) -- starts the history over (and the output is that sample,
 * unchanged); otherwise history += w (1/z - history) with w =
 * max(1/count, 1 - alpha), and the output is 1 / history (the sample itself
 * where the history equals its 1/z: a still, clean scene passes unchanged).  Where it has none,
 * the history waits for it (the test decides when it returns) and the output
 * is the history for the first `persist` frames, then no data.
 * The scalar reference (the oracle); pixels [i0, i1) for the tails of the
 * optimised kernels, which agree with it bit for bit.
 */
void dao_temporal_depth_ref(const struct dao_temporal_depth_setup *s, float *z, float *hist,
			    uint8_t *count, uint8_t *age, int y0, int y1);
void dao_temporal_depth_span_ref(const struct dao_temporal_depth_setup *s, float *z, float *hist,
				 uint8_t *count, uint8_t *age, size_t i0, size_t i1);

#define DAO_TEMPORAL_DEPTH_SIMD_PROTO(isa)                                                    \
	void dao_temporal_depth_##isa(const struct dao_temporal_depth_setup *s, float *z,     \
				      float *hist, uint8_t *count, uint8_t *age, int y0, int y1)

DAO_TEMPORAL_DEPTH_SIMD_PROTO(generic);
DAO_TEMPORAL_DEPTH_SIMD_PROTO(sse41);
DAO_TEMPORAL_DEPTH_SIMD_PROTO(avx2);
DAO_TEMPORAL_DEPTH_SIMD_PROTO(avx512);

#endif
