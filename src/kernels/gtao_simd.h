/* SPDX-License-Identifier: MIT */
#ifndef DAO_KERNELS_GTAO_SIMD_H
#define DAO_KERNELS_GTAO_SIMD_H

#include "kernels/gtao.h"
#include "kernels/ao_variants.h"
#include "kernels/gtao_planes.h"
#include "kernels/gtao_tile.h"

/*
 * Optimised GTAO, one build per instruction set (gtao_<isa>.c).  Besides the
 * reference's inputs it reads the depth planes of gtao_planes.h: the phase
 * plane with tile noise (x_begin then a multiple of DAO_GTAO_BLOCK_SPAN),
 * the bordered plane otherwise.  sc: the calling thread's scratch
 * (gtao_tile.h), used with tile noise.
 */
#define DAO_GTAO_SIMD_PROTO(isa)                                                          \
	void dao_gtao_simd_##isa(const struct dao_gtao_setup *s, const float *z,          \
				 const struct dao_gtao_planes *pl, const float *n, float *ao,    \
				 int y0, int y1, struct dao_tile_scratch *sc)

/*
 * Optimised VBAO (with tile noise; the reference with any other): as
 * dao_vbao_ref, from the same planes as the GTAO kernel, and with a
 * thickness plane (v->thickness) from pl->thick, which must hold it
 * (dao_gtao_planes_fill_thickness).
 */
#define DAO_VBAO_SIMD_PROTO(isa)                                                          \
	void dao_vbao_simd_##isa(const struct dao_variant_setup *v, const float *z,       \
				 const struct dao_gtao_planes *pl, const float *n, float *ao,    \
				 int y0, int y1, struct dao_tile_scratch *sc)

/*
 * Optimised HBAO (with tile noise; the reference with any other): as
 * dao_hbao_ref, from the phase plane of the GTAO kernel.
 */
#define DAO_HBAO_SIMD_PROTO(isa)                                                          \
	void dao_hbao_simd_##isa(const struct dao_variant_setup *v, const float *z,       \
				 const struct dao_gtao_planes *pl, const float *n, float *ao,    \
				 int y0, int y1, struct dao_tile_scratch *sc)

/* dao_gtao_planes_fill over SIMD lanes (the same values) */
#define DAO_GTAO_PLANES_FILL_PROTO(isa)                                                   \
	void dao_gtao_planes_fill_##isa(struct dao_gtao_planes *pl, const float *z, int phase, \
					int y0, int y1)

DAO_GTAO_SIMD_PROTO(generic);
DAO_GTAO_SIMD_PROTO(sse41);
DAO_GTAO_SIMD_PROTO(avx2);
DAO_GTAO_SIMD_PROTO(avx512);
DAO_VBAO_SIMD_PROTO(generic);
DAO_VBAO_SIMD_PROTO(sse41);
DAO_VBAO_SIMD_PROTO(avx2);
DAO_VBAO_SIMD_PROTO(avx512);
DAO_HBAO_SIMD_PROTO(generic);
DAO_HBAO_SIMD_PROTO(sse41);
DAO_HBAO_SIMD_PROTO(avx2);
DAO_HBAO_SIMD_PROTO(avx512);
DAO_GTAO_PLANES_FILL_PROTO(generic);
DAO_GTAO_PLANES_FILL_PROTO(sse41);
DAO_GTAO_PLANES_FILL_PROTO(avx2);
DAO_GTAO_PLANES_FILL_PROTO(avx512);

#endif
