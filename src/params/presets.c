/* SPDX-License-Identifier: MIT */
/*
 * Quality presets.  The medium preset is the default of the library and the
 * CLI; its values were tuned against the ray-traced ground truth of the
 * synthetic scenes (`depthao eval`, table in docs/accuracy.md).  The prefilter is
 * the domain filter driven by the noise measured in every frame
 * (noise-model=auto, depth/noise_estimate.h): on clean, Gaussian-noisy and
 * structured-light depth alike, without naming the sensor.
 */
#include "params/presets.h"

#include "params/params_abi.h"

static const struct dao_params common = {
	.size = sizeof(struct dao_params),
	.depth_min = 0.05f,
	.depth_max = 20.0f,
	.prefilter = DAO_PREFILTER_DOMAIN,
	.depth_noise = 0.0012f,
	.prefilter_radius = 3,
	.prefilter_scale = 4.0f,
	.prefilter_range = 3.0f,
	.prefilter_iterations = 2,
	.noise_model = DAO_NOISE_MODEL_AUTO,
	.normals = DAO_NORMALS_WIDE,
	.normal_radius = 4,
	.algorithm = DAO_ALGORITHM_GTAO,
	.radius = 0.5f,
	.falloff = 0.2f,
	.slices = 2,
	.steps = 6,
	.thickness = 0.0f,
	.max_screen_radius = 160.0f,
	.min_screen_radius = 0.0f,
	.distribution_power = 1.0f,
	.noise = DAO_NOISE_TILE,
	.final_power = 1.0f,
	.albedo = 0.0f,
	.invalid_value = 1.0f,
	.strength = 1.0f,
	.hbao_bias = 20.0f,
	.ssao_min = 0.02f,
	.ssao_max = 0.5f,
	.edl_radius = 1.5f,
	.vbao_thickness = 0.2f,
	.vbao_thickness_mode = DAO_VBAO_THICKNESS_IMAGE,
	.vbao_thickness_max = 0.5f,
	.noise_interval = 1,
	.temporal = 0.0f,
	.temporal_reject = 0.02f,
	.depth_temporal = 0.0f,
	.depth_temporal_reject = 3.0f,
	.depth_temporal_persist = 0,
	.threads = 0,
	.simd = DAO_SIMD_AUTO,
	.denoise = DAO_DENOISE_PLANE,
	.denoise_radius = 4,
	.denoise_sharpness = 4.0f,
	.shade = DAO_SHADE_LAMBERT,
	.near_m = 0.0f,
	.far_m = 0.0f,
	.shade_power = 1.0f,
	.occlusion_color = 0x000000,
};

void dao_preset_fill(struct dao_params *p, enum dao_quality q)
{
	*p = common;
	switch (q) {
	case DAO_QUALITY_LOW:
		p->slices = 1;
		break;
	case DAO_QUALITY_MEDIUM:
	case DAO_QUALITY_COUNT:
		break;
	case DAO_QUALITY_HIGH:
		p->slices = 4;
		p->steps = 8;
		break;
	case DAO_QUALITY_ULTRA:
		p->slices = 8;
		p->steps = 12;
		p->denoise = DAO_DENOISE_BILATERAL;
		break;
	}
}

/*
 * Streams: the temporal depth filter with a history share of 0.8 (the noise
 * of 1/z falls to a third once settled, sqrt((1 - a) / (1 + a)); the first
 * five frames are a plain mean).  Chosen on the boxes and spheres sequences
 * of tests/pipeline/test_temporal_depth.c; docs/accuracy.md has the measurements.
 * The noise is measured fully every DAO_STREAM_NOISE_INTERVAL frames (half
 * a second at 30 fps) and where the scene moves in between
 * (depth/noise_reuse.h).
 */
#define DAO_STREAM_NOISE_INTERVAL 15

void dao_params_stream_defaults(struct dao_params *p)
{
	if (dao_params_check_size(p, NULL) < 0)
		return; /* dao_params_validate() reports it */
	p->depth_temporal = 0.8f;
	if (dao_params_has(p, offsetof(struct dao_params, noise_interval), sizeof p->noise_interval))
		p->noise_interval = DAO_STREAM_NOISE_INTERVAL;
}
