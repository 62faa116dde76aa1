/* SPDX-License-Identifier: MIT */
#include "depth/noise_estimate.h"
#include "depth/prefilter.h"
#include "kernels/gtao_simd.h"
#include "normals/normals.h"
#include "pipeline/kernels.h"

static void gtao_reference(const struct dao_gtao_setup *s, const float *z,
			   const struct dao_gtao_planes *pl, const float *n, float *ao, int y0, int y1,
			   struct dao_tile_scratch *sc)
{
	(void)pl;
	(void)sc;
	dao_gtao_ref(s, z, n, ao, y0, y1);
}

static void vbao_reference(const struct dao_variant_setup *v, const float *z,
			   const struct dao_gtao_planes *pl, const float *n, float *ao, int y0, int y1,
			   struct dao_tile_scratch *sc)
{
	(void)pl;
	(void)sc;
	dao_vbao_ref(v, z, n, ao, y0, y1);
}

static void hbao_reference(const struct dao_variant_setup *v, const float *z,
			   const struct dao_gtao_planes *pl, const float *n, float *ao, int y0, int y1,
			   struct dao_tile_scratch *sc)
{
	(void)pl;
	(void)sc;
	dao_hbao_ref(v, z, n, ao, y0, y1);
}

#define KERNELS(isa)                                                                         \
	(struct dao_kernels)                                                                 \
	{                                                                                    \
		.prefilter_h = dao_prefilter_h_##isa, .prefilter_v = dao_prefilter_v_##isa,  \
		.domain_pass = dao_domain_pass_##isa,                                        \
		.gtao = dao_gtao_simd_##isa, .vbao = dao_vbao_simd_##isa,                    \
		.hbao = dao_hbao_simd_##isa,                                                 \
		.planes_fill = dao_gtao_planes_fill_##isa,                                   \
		.denoise_plane = dao_denoise_plane_##isa,                                    \
		.normals = dao_normals_from_depth_##isa, .shade = dao_shade_##isa,           \
		.temporal_depth = dao_temporal_depth_##isa,                                  \
		.noise_row = dao_noise_row_##isa,                                            \
		.icp_pairs = dao_icp_pairs_##isa,                                            \
		.icp_source = dao_icp_source_##isa, .icp_target = dao_icp_target_##isa,      \
		.reproject_land = dao_reproject_land_##isa,                                  \
		.ao_reproject = dao_ao_history_reproject_rows_##isa,                         \
	}

void dao_kernels_select(struct dao_kernels *k, enum dao_simd simd)
{
	switch (simd) {
#if DAO_HAVE_X86_KERNELS
	case DAO_SIMD_AVX512:
		*k = KERNELS(avx512);
		break;
	case DAO_SIMD_AVX2:
		*k = KERNELS(avx2);
		break;
	case DAO_SIMD_SSE41:
		*k = KERNELS(sse41);
		break;
#endif
	case DAO_SIMD_GENERIC:
		*k = KERNELS(generic);
		break;
	default:
		*k = (struct dao_kernels){
			.prefilter_h = dao_prefilter_h_ref,
			.prefilter_v = dao_prefilter_v_ref,
			.domain_pass = dao_domain_pass_ref,
			.gtao = gtao_reference,
			.vbao = vbao_reference,
			.hbao = hbao_reference,
			.planes_fill = dao_gtao_planes_fill,
			.denoise_plane = dao_denoise_plane,
			.normals = dao_normals_from_depth,
			.shade = dao_shade,
			.temporal_depth = dao_temporal_depth_ref,
			.noise_row = dao_noise_row_ref,
			.icp_pairs = dao_icp_pairs_ref,
			.icp_source = dao_icp_source_ref,
			.icp_target = dao_icp_target_ref,
			.reproject_land = dao_reproject_land_ref,
			.ao_reproject = dao_ao_history_reproject_rows,
		};
		simd = DAO_SIMD_REFERENCE;
		break;
	}
	k->simd = simd;
}
