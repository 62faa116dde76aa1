/* SPDX-License-Identifier: MIT */
/*
 * A periodic pattern in an AO image, measured: the AO's spectral power at the
 * frequencies of the 4 x 4 noise tile over windows where the surface is
 * smooth and occluded, against the power at neighbouring frequencies.  A
 * visible grid is a peak (ratio >> 1); no pattern gives about 1.  Tools and
 * tests only.
 */
#ifndef DAO_SYNTH_PATTERN_H
#define DAO_SYNTH_PATTERN_H

/* The distinct non-zero frequencies of a 4-pixel lattice, cycles per pixel
 * (the others are their mirror images, with the same power). */
#define SYNTH_PATTERN_FREQS 9
extern const float synth_pattern_freq[SYNTH_PATTERN_FREQS][2];

/* Windows are WIN x WIN pixels, every WIN / 2 pixels. */
#define SYNTH_PATTERN_WIN 32

struct synth_pattern {
	int windows;                           /* windows that qualified */
	double ratio[SYNTH_PATTERN_FREQS];     /* power at f / mean power around f */
	double amplitude[SYNTH_PATTERN_FREQS]; /* the component's amplitude, AO units */
	double max_ratio;                      /* the largest ratio */
	int max_index;                         /* ... at synth_pattern_freq[max_index] */
};

/*
 * Measures `ao` (visibility, w x h floats) over windows in which at least 90 %
 * of the pixels have depth (`depth` in metres, 0 = none), the mean AO there is
 * below 0.95 and the depth has no edge (second differences of 1/z along both
 * axes below 0.02 / m; 1/z is affine on planes).  In each window the AO's
 * least-squares plane is removed (pixels without depth are set on it) and a
 * Hann window applied; the DFT power at each tile frequency and at eight
 * neighbours 3 bins away (3/WIN cycles/px in x, y or both) is summed over all
 * windows.  Returns 0, or -ENOENT (with out->windows = 0) when no window
 * qualifies.
 */
int synth_pattern_measure(const float *ao, const float *depth, int w, int h,
			  struct synth_pattern *out);

#endif
