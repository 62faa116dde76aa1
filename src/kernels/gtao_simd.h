/* SPDX-License-Identifier: MIT */
#ifndef DAO_KERNELS_GTAO_SIMD_H
#define DAO_KERNELS_GTAO_SIMD_H

#include "kernels/gtao.h"

/*
 * Optimised GTAO, one build per instruction set (gtao_<isa>.c).  Besides the
 * reference's inputs it reads izp: 1/z (0 = no data) with a one-pixel border
 * of zeros, (width + 2) x (height + 2), pointing at pixel (-1, -1).
 */
#define DAO_GTAO_SIMD_PROTO(isa)                                                          \
	void dao_gtao_simd_##isa(const struct dao_gtao_setup *s, const float *z,          \
				 const float *izp, const float *n, float *ao, int y0, int y1)

DAO_GTAO_SIMD_PROTO(generic);
DAO_GTAO_SIMD_PROTO(sse41);
DAO_GTAO_SIMD_PROTO(avx2);

#endif
