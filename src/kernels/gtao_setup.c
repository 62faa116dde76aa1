/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/math_util.h"
#include "kernels/gtao.h"
#include "kernels/noise.h"

void dao_gtao_setup_init(struct dao_gtao_setup *s, const struct dao_camera *cam,
			 const struct dao_params *p, uint64_t frame_index)
{
	const float R = dao_gtao_effective_radius(p->radius, p->steps);
	/* the weight falls linearly from 1 at R(1 - f/2) to 0 at R(1 + f/2): centred on
	 * R, so on average it matches the hard radius of the ground-truth definition */
	const float half = 0.5f * p->falloff * R;
	/* thickness is the pull per sample at 8 steps; scale it so the pull over the
	 * whole radius does not depend on the step count */
	const float decay = powf(1.0f - p->thickness, 8.0f / (float)p->steps);
	*s = (struct dao_gtao_setup){
		.width = (int)cam->width,
		.x_begin = 0,
		.x_end = (int)cam->width,
		.height = (int)cam->height,
		.ax = cam->ax, .ay = cam->ay, .bx = cam->bx, .by = cam->by,
		.focal = (float)(0.5 * (cam->fx + cam->fy)),
		.search_radius = R + half,
		.decay = decay,
		.max_r_px = p->max_screen_radius,
		.min_r_px = p->min_screen_radius,
		.power = p->distribution_power,
		.slices = p->slices,
		.steps = p->steps,
		.noise = p->noise,
		.frame = (uint32_t)frame_index,
		.final_power = p->final_power,
		.albedo = p->albedo,
		.invalid_value = p->invalid_value,
	};
	if (half > 0.0f) {
		s->falloff_mul = -1.0f / (2.0f * half);
		s->falloff_add = (R + half) / (2.0f * half);
	} else {
		/* hard cut at R */
		s->falloff_mul = -1e30f;
		s->falloff_add = R * 1e30f;
	}
}

void dao_gtao_fill_r2_tile(float *tile, uint64_t frame_index)
{
	for (int y = 0; y < 64; y++)
		for (int x = 0; x < 64; x++)
			dao_r2(x, y, (uint32_t)frame_index, &tile[y * 64 + x], &tile[4096 + y * 64 + x]);
}

float dao_gtao_block_izmax(const struct dao_gtao_setup *s, const float *z, int x, int y)
{
	const int x0 = (x & ~(DAO_GTAO_BLOCK_SPAN - 1)) + (x & 3);
	float izmax = 0.0f;
	for (int k = 0; k < DAO_GTAO_BLOCK; k++) {
		const int xx = x0 + 4 * k;
		if (xx >= s->width)
			break;
		const float zz = z[(size_t)y * s->width + xx];
		/* 1/z as the optimised kernels store it, so both round alike */
		const float iz = zz > 0.0f ? 1.0f / zz : 0.0f;
		izmax = iz > izmax ? iz : izmax;
	}
	return izmax;
}

float dao_gtao_block_radius(const struct dao_gtao_setup *s, const float *z, int x, int y)
{
	return dao_gtao_quantize_radius(s->search_radius * s->focal * dao_gtao_block_izmax(s, z, x, y));
}


void dao_gtao_noise(const struct dao_gtao_setup *s, int x, int y, float *n0, float *n1)
{
	switch (s->noise) {
	case DAO_NOISE_IGN:
		*n0 = dao_ign(x, y, s->frame);
		/* swapped axes give a second IGN field uncorrelated with the first */
		*n1 = dao_ign(y + 7, x + 13, s->frame);
		break;
	case DAO_NOISE_R2:
		dao_r2(x, y, s->frame, n0, n1);
		break;
	case DAO_NOISE_TILE:
		dao_tile_noise(x, y, s->frame, n0, n1);
		break;
	default:
		*n0 = 0.5f;
		*n1 = 0.5f;
		break;
	}
}

float dao_gtao_finish(const struct dao_gtao_setup *s, float vis)
{
	vis = dao_saturate(vis);
	if (s->final_power != 1.0f)
		vis = powf(vis, s->final_power);
	if (s->albedo > 0.0f) {
		/* multi-bounce fit, Jimenez et al. 2016 eq. 10 */
		const float rho = s->albedo;
		const float a = 2.0404f * rho - 0.3324f;
		const float b = -4.7951f * rho + 0.6417f;
		const float c = 2.7552f * rho + 0.6903f;
		vis = fmaxf(vis, ((a * vis + b) * vis + c) * vis);
	}
	return dao_saturate(vis);
}
