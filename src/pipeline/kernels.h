/* SPDX-License-Identifier: MIT */
/* The per-stage kernels of one kernel set (reference or an instruction set). */
#ifndef DAO_PIPELINE_KERNELS_H
#define DAO_PIPELINE_KERNELS_H

#include <depthao/params.h>

#include "denoise/denoise.h"
#include "depth/domain.h"
#include "depth/prefilter.h"
#include "kernels/ao_variants.h"
#include "kernels/gtao.h"
#include "kernels/gtao_planes.h"
#include "kernels/gtao_tile.h"
#include "motion/ao_reproject.h"
#include "motion/icp_pairs.h"
#include "motion/icp_source.h"
#include "motion/reproject.h"
#include "pipeline/temporal_depth.h"
#include "shade/shade.h"

struct dao_kernels {
	enum dao_simd simd;
	void (*prefilter_h)(const struct dao_prefilter_setup *s, const float *z, float *tmp, int y0,
			    int y1);
	void (*prefilter_v)(const struct dao_prefilter_setup *s, const float *tmp, float *out,
			    int y0, int y1);
	/* prefilter=domain: one pass over lanes [lane0, lane1) (domain.h) */
	void (*domain_pass)(const struct dao_domain_pass *p, float *scratch, int lane0, int lane1);
	/* pl: the 1/z planes of gtao_planes.h, sc: the thread's scratch (gtao_tile.h),
	 * both used by the optimised kernels only */
	void (*gtao)(const struct dao_gtao_setup *s, const float *z,
		     const struct dao_gtao_planes *pl, const float *n, float *ao, int y0, int y1,
		     struct dao_tile_scratch *sc);
	void (*vbao)(const struct dao_variant_setup *v, const float *z,
		     const struct dao_gtao_planes *pl, const float *n, float *ao, int y0, int y1,
		     struct dao_tile_scratch *sc);
	void (*hbao)(const struct dao_variant_setup *v, const float *z,
		     const struct dao_gtao_planes *pl, const float *n, float *ao, int y0, int y1,
		     struct dao_tile_scratch *sc);
	/* fills the planes (dao_gtao_planes_fill) */
	void (*planes_fill)(struct dao_gtao_planes *pl, const float *z, int phase, int y0, int y1);
	void (*denoise_plane)(const struct dao_denoise_setup *s, const float *z, const float *ao_in,
			      float *ao_out, int y0, int y1);
	void (*normals)(const struct dao_camera *cam, const float *z, int r, float *n, int y0,
			int y1);
	void (*shade)(const struct dao_shade_setup *s, const float *z, const float *n,
		      const float *ao, const struct dao_frame *out, int y0, int y1);
	/* noise-model=auto: the block statistics of a block row (noise_estimate.h) */
	void (*noise_row)(const float *z, int stride, int nblocks, float *out);
	void (*temporal_depth)(const struct dao_temporal_depth_setup *s, float *z, float *hist,
			       uint8_t *count, uint8_t *age, int y0, int y1);
	/* depth-temporal-motion=icp: one step's pairs (motion/icp_pairs.h) */
	dao_icp_pairs_fn icp_pairs;
	/* ... its source grid and target depth (motion/icp_source.h) */
	dao_icp_source_fn icp_source;
	dao_icp_target_fn icp_target;
	/* ... and the history's landing pass (motion/reproject.h) */
	dao_reproject_land_fn reproject_land;
	/* the AO history's (motion/ao_reproject.h) */
	dao_ao_reproject_fn ao_reproject;
};

/* The kernels of `simd` (AUTO resolved by the caller; must be supported). */
void dao_kernels_select(struct dao_kernels *k, enum dao_simd simd);

#endif
