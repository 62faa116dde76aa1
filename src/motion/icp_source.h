/* SPDX-License-Identifier: MIT */
/*
 * The motion estimate's per-frame inputs (motion/icp.h) as kernels: the
 * source grid with its normals, a grid row at a time, and the target's depth
 * from the history's 1/z.  The reference (icp_source.c) is the oracle; the
 * kernel sets (icp_source_simd.inc.c) compute the same float operations in
 * the same order (no FMA, IEEE division and square root), so their output is
 * the reference's to the bit (tests/pipeline/test_icp_source.c).
 *
 * A grid point is pixel (x, y), x and y multiples of `step`: its position
 * (x ax + bx, y ay + by, 1) z and its normal from central differences over
 * `r` pixels, towards the camera; none within r pixels of the border, where
 * the pixel or a neighbour has no depth, at a depth edge (a neighbour more
 * than edge r z off the centre's depth) or where the differences are
 * parallel.
 */
#ifndef DAO_MOTION_ICP_SOURCE_H
#define DAO_MOTION_ICP_SOURCE_H

#include <stddef.h>
#include <stdint.h>

struct dao_icp_grid {
	const float *z;   /* current depth, m (0 = none), w x h */
	int w, h, r, step;
	int gw;           /* grid columns, ceil(w / step) */
	size_t stride;    /* floats from one output plane to the next, >= gw rounded up to
			   * DAO_ICP_PAD */
	float edge_r;     /* edge * r: a neighbour off by more than edge_r z is an edge */
	float ax, bx, ay, by; /* pixel -> ray: x ax + bx */
	float rax, ray;   /* r ax, r ay */
};

/* Grid row y (a pixel row, a multiple of step), grid columns 0 .. gw - 1,
 * into out: six planes `stride` apart (x, y, z, nx, ny, nz); all six 0 where
 * the grid point has no point (z > 0 marks one).  Writes columns up to gw
 * rounded up to DAO_ICP_PAD. */
typedef void (*dao_icp_source_fn)(const struct dao_icp_grid *g, int y, float *out);

/* The target's depth: tz = 1 / inv where inv > 0 and (count NULL or
 * count != 0), else 0, for i in [i0, i1). */
typedef void (*dao_icp_target_fn)(const float *inv, const uint8_t *count, float *tz, size_t i0,
				  size_t i1);

void dao_icp_source_ref(const struct dao_icp_grid *g, int y, float *out);
void dao_icp_target_ref(const float *inv, const uint8_t *count, float *tz, size_t i0, size_t i1);

#define DAO_ICP_SOURCE_PROTO(isa)                                                             \
	void dao_icp_source_##isa(const struct dao_icp_grid *g, int y, float *out);           \
	void dao_icp_target_##isa(const float *inv, const uint8_t *count, float *tz, size_t i0, \
				  size_t i1)
DAO_ICP_SOURCE_PROTO(generic);
DAO_ICP_SOURCE_PROTO(sse41);
DAO_ICP_SOURCE_PROTO(avx2);
DAO_ICP_SOURCE_PROTO(avx512);

#endif
