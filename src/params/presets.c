/* SPDX-License-Identifier: MIT */
/*
 * Quality presets: the defaults of the parameter table (param_rows.h), and
 * only what each preset changes in them.  The medium preset is the table's
 * defaults unchanged, the default of the library and the CLI; those values
 * were tuned against the ray-traced ground truth of the synthetic scenes
 * (`depthao eval`, table in docs/accuracy.md).  The prefilter is
 * the domain filter driven by the noise measured in every frame
 * (noise-model=auto, depth/noise_estimate.h): on clean, Gaussian-noisy and
 * structured-light depth alike, without naming the sensor.
 */
#include "params/presets.h"

#include "params/params_abi.h"

void dao_preset_fill(struct dao_params *p, enum dao_quality q)
{
	*p = dao_param_defaults;
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
