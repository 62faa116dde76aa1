/* SPDX-License-Identifier: MIT */
/* The librealsense-style reference chain; see rs_reference.h. */
#include "synth/rs_reference.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

void rs_ref_options_default(struct rs_ref_options *o)
{
	*o = (struct rs_ref_options){
		.spatial_alpha = 0.5f, .spatial_delta = 20.0f, .spatial_iterations = 2,
		.temporal_alpha = 0.4f, .temporal_delta = 20.0f,
		.persist_valid = 2, .persist_of = 4, .hole_fill = 1,
	};
}

int rs_ref_init(struct rs_ref *r, const struct rs_ref_options *o, int w, int h, double fx,
		struct dao_error *err)
{
	memset(r, 0, sizeof *r);
	if (w <= 0 || h <= 0 || !(fx > 0.0) || o->persist_of < 1 || o->persist_of > 8)
		return dao_error_set(err, -EINVAL, "reference chain: bad size, focal length or "
				     "persistence window");
	const size_t np = (size_t)w * h;
	r->o = *o;
	r->w = w;
	r->h = h;
	r->k = fx * RS_REF_BASELINE * RS_REF_SUBPIXEL;
	r->disp = malloc(np * sizeof(float));
	r->hist = calloc(np, sizeof(float));
	r->valid = calloc(np, 1);
	if (!r->disp || !r->hist || !r->valid) {
		rs_ref_free(r);
		return dao_error_set(err, -ENOMEM, "reference chain: out of memory");
	}
	return 0;
}

void rs_ref_free(struct rs_ref *r)
{
	free(r->disp);
	free(r->hist);
	free(r->valid);
	r->disp = r->hist = NULL;
	r->valid = NULL;
}

void rs_ref_reset(struct rs_ref *r)
{
	memset(r->hist, 0, (size_t)r->w * r->h * sizeof(float));
	memset(r->valid, 0, (size_t)r->w * r->h);
	r->frames = 0;
}

/* One recursive pass over n samples `step` apart: an exponential moving average that
 * restarts at a hole or at a step of delta or more. */
static void pass(float *p, int n, ptrdiff_t step, float alpha, float delta)
{
	float prev = 0.0f;
	for (int i = 0; i < n; i++, p += step) {
		const float cur = *p;
		if (!(cur > 0.0f)) {
			prev = 0.0f;
			continue;
		}
		if (prev > 0.0f && fabsf(cur - prev) < delta)
			*p = alpha * cur + (1.0f - alpha) * prev;
		prev = *p;
	}
}

void rs_ref_spatial(float *d, int w, int h, float alpha, float delta, int iterations)
{
	for (int it = 0; it < iterations; it++) {
		for (int y = 0; y < h; y++) {
			pass(d + (size_t)y * w, w, 1, alpha, delta);
			pass(d + (size_t)y * w + w - 1, w, -1, alpha, delta);
		}
		for (int x = 0; x < w; x++) {
			pass(d + x, h, w, alpha, delta);
			pass(d + (size_t)(h - 1) * w + x, h, -(ptrdiff_t)w, alpha, delta);
		}
	}
}

static int popcount8(unsigned v)
{
	int c = 0;
	for (; v; v &= v - 1)
		c++;
	return c;
}

/* The temporal filter on disparity, in place, with its history. */
static void temporal(struct rs_ref *r, float *d)
{
	const unsigned window = (1u << r->o.persist_of) - 1u;
	for (size_t i = 0; i < (size_t)r->w * r->h; i++) {
		const float h = r->hist[i];
		const unsigned past = r->valid[i];
		if (d[i] > 0.0f) {
			if (h > 0.0f && fabsf(d[i] - h) < r->o.temporal_delta)
				d[i] = r->o.temporal_alpha * d[i] + (1.0f - r->o.temporal_alpha) * h;
			r->hist[i] = d[i];
			r->valid[i] = (uint8_t)((past << 1) | 1u);
		} else {
			if (h > 0.0f && popcount8(past & window) >= r->o.persist_valid)
				d[i] = h;
			r->valid[i] = (uint8_t)(past << 1);
		}
	}
}

void rs_ref_hole_fill_farthest(float *z, int w, int h)
{
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			if (z[i] > 0.0f)
				continue;
			float best = 0.0f;
			if (y > 0)
				best = fmaxf(best, z[i - w]);
			if (y < h - 1)
				best = fmaxf(best, z[i + w]);
			if (x > 0)
				best = fmaxf(best, z[i - 1]);
			if (x < w - 1)
				best = fmaxf(best, z[i + 1]);
			z[i] = best;
		}
}

void rs_ref_process(struct rs_ref *r, const float *in, float *out)
{
	const size_t np = (size_t)r->w * r->h;
	const float k = (float)r->k;
	for (size_t i = 0; i < np; i++)
		r->disp[i] = in[i] > 0.0f ? k / in[i] : 0.0f;
	rs_ref_spatial(r->disp, r->w, r->h, r->o.spatial_alpha, r->o.spatial_delta,
		       r->o.spatial_iterations);
	temporal(r, r->disp);
	for (size_t i = 0; i < np; i++)
		out[i] = r->disp[i] > 0.0f ? k / r->disp[i] : 0.0f;
	if (r->o.hole_fill)
		rs_ref_hole_fill_farthest(out, r->w, r->h);
	r->frames++;
}
