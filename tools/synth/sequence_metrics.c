/* SPDX-License-Identifier: MIT */
/* Metrics of an AO sequence against per-frame truth (sequence_metrics.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "synth/sequence_metrics.h"

#define NEVER (-1000)

int synth_seq_masks_init(struct synth_seq_masks *m, int width, int height, int with_truth)
{
	memset(m, 0, sizeof *m);
	const size_t np = (size_t)width * (size_t)height;
	m->width = width, m->height = height, m->with_truth = with_truth;
	m->last_swept = malloc(np * sizeof *m->last_swept);
	m->ref = malloc(np * sizeof *m->ref);
	m->prev_true = calloc(np, sizeof *m->prev_true);
	m->is_static = malloc(np);
	if (!m->last_swept || !m->ref || !m->prev_true || !m->is_static) {
		synth_seq_masks_free(m);
		return -ENOMEM;
	}
	for (size_t i = 0; i < np; i++)
		m->last_swept[i] = NEVER;
	memset(m->is_static, 1, np);
	return 0;
}

void synth_seq_masks_free(struct synth_seq_masks *m)
{
	free(m->last_swept);
	free(m->ref);
	free(m->prev_true);
	free(m->is_static);
	memset(m, 0, sizeof *m);
}

/* A discontinuity passed: the surface changed by more than SYNTH_TRAIL_REL, or appeared/vanished. */
static int swept(float a, float b)
{
	if ((a > 0.0f) != (b > 0.0f))
		return 1;
	return a > 0.0f && fabsf(a - b) > SYNTH_TRAIL_REL * fminf(a, b);
}

void synth_seq_masks_add(struct synth_seq_masks *m, const float *depth, const float *true_depth)
{
	const size_t np = (size_t)m->width * (size_t)m->height;
	const int32_t k = (int32_t)m->frame;
	const float *ref_now = m->with_truth && true_depth ? true_depth : depth;
	for (size_t i = 0; i < np; i++) {
		if (!(depth[i] > 0.0f))
			m->is_static[i] = 0;
		if (k == 0) {
			m->ref[i] = ref_now[i];
		} else if (m->with_truth && true_depth) {
			if (fabsf(true_depth[i] - m->ref[i]) > SYNTH_STATIC_TOL_M)
				m->is_static[i] = 0;
			if (swept(m->prev_true[i], true_depth[i]))
				m->last_swept[i] = k;
		} else if (fabsf(depth[i] - m->ref[i]) > SYNTH_STATIC_REL * m->ref[i]) {
			m->is_static[i] = 0;
		}
		if (true_depth)
			m->prev_true[i] = true_depth[i];
	}
	m->frame++;
}

int synth_seq_column_init(struct synth_seq_column *c, int width, int height)
{
	memset(c, 0, sizeof *c);
	const size_t np = (size_t)width * (size_t)height;
	c->width = width, c->height = height;
	c->sum = calloc(np, sizeof *c->sum);
	c->sumsq = calloc(np, sizeof *c->sumsq);
	c->prev = calloc(np, sizeof *c->prev);
	c->prev_valid = calloc(np, 1);
	c->tsum = calloc(np, sizeof *c->tsum);
	c->tsumsq = calloc(np, sizeof *c->tsumsq);
	c->tn = calloc(np, sizeof *c->tn);
	if (!c->sum || !c->sumsq || !c->prev || !c->prev_valid || !c->tsum || !c->tsumsq || !c->tn) {
		synth_seq_column_free(c);
		return -ENOMEM;
	}
	return 0;
}

void synth_seq_column_free(struct synth_seq_column *c)
{
	free(c->sum);
	free(c->sumsq);
	free(c->prev);
	free(c->prev_valid);
	free(c->tsum);
	free(c->tsumsq);
	free(c->tn);
	memset(c, 0, sizeof *c);
}

void synth_seq_column_add(struct synth_seq_column *c, const struct synth_seq_masks *m,
			  const float *ao, const float *gt, const float *depth,
			  struct synth_seq_frame *out)
{
	const size_t np = (size_t)c->width * (size_t)c->height;
	double e_sum = 0.0, t_sum = 0.0;
	long n = 0, tn = 0;
	if (c->offered++ < c->skip) {
		if (out)
			*out = (struct synth_seq_frame){ 0 };
		return;
	}
	for (size_t i = 0; i < np; i++) {
		const int valid = depth[i] > 0.0f;
		const double a = ao[i];
		c->sum[i] += a;
		c->sumsq[i] += a * a;
		if (valid && c->prev_valid[i]) {
			c->change_sum += fabs(a - c->prev[i]);
			c->change_n++;
		}
		c->prev[i] = ao[i];
		c->prev_valid[i] = (uint8_t)valid;
		if (!gt || !valid)
			continue;
		const double e = fabs(a - gt[i]);
		e_sum += e;
		n++;
		if (m && m->with_truth && synth_seq_in_band(m, (long)i)) {
			t_sum += e;
			tn++;
		}
	}
	c->frames++;
	if (out)
		*out = (struct synth_seq_frame){ .mae = n ? e_sum / n : 0.0, .count = n,
						 .trail_mae = tn ? t_sum / tn : 0.0, .trail_count = tn };
}

double synth_seq_flicker(const struct synth_seq_column *c, const struct synth_seq_masks *m,
			 long *count)
{
	const size_t np = (size_t)c->width * (size_t)c->height;
	double s = 0.0;
	long n = 0;
	for (size_t i = 0; i < np && c->frames > 1; i++) {
		if (!m->is_static[i])
			continue;
		const double mean = c->sum[i] / c->frames;
		const double var = c->sumsq[i] / c->frames - mean * mean;
		s += sqrt(var > 0.0 ? var : 0.0);
		n++;
	}
	if (count)
		*count = n;
	return n ? s / n : 0.0;
}

double synth_seq_change(const struct synth_seq_column *c)
{
	return c->change_n ? c->change_sum / c->change_n : 0.0;
}

int synth_seq_track_init(struct synth_seq_track *t, int width, int height, double fx, double fy,
			 double cx, double cy)
{
	*t = (struct synth_seq_track){ .width = width, .height = height, .fx = fx, .fy = fy,
				       .cx = cx, .cy = cy };
	t->X = malloc((size_t)width * (size_t)height * 3 * sizeof *t->X);
	return t->X ? 0 : -ENOMEM;
}

void synth_seq_track_free(struct synth_seq_track *t)
{
	free(t->X);
	memset(t, 0, sizeof *t);
}

void synth_seq_track_frame(struct synth_seq_track *t, const float *true_depth,
			   const struct synth_pose *pose)
{
	if (t->frames++ > 0)
		return;
	for (int y = 0; y < t->height; y++)
		for (int x = 0; x < t->width; x++) {
			const size_t i = (size_t)y * t->width + x;
			const double z = true_depth[i];
			const double c[3] = { (x - t->cx) / t->fx * z, (y - t->cy) / t->fy * z, z };
			for (int k = 0; k < 3; k++)
				t->X[3 * i + k] = z > 0.0 ? (float)(pose->R[k][0] * c[0] + pose->R[k][1] * c[1] +
								    pose->R[k][2] * c[2] + pose->t[k])
							  : NAN;
		}
}

/*
 * The AO where frame `pose` sees world point X: bilinear over the four pixels
 * around its projection (a tap of weight SYNTH_TRACK_MIN_WEIGHT or less left
 * out and the others' weights renormalised: the float points of a still
 * camera land within 1e-5 px of a pixel centre), each of which must have
 * input depth and a true depth that agrees with the point's; 0 with *ok = 0
 * where one does not or it falls outside the image.  Bilinear, not the
 * nearest pixel: the nearest's up to half a pixel of rounding, which changes
 * from frame to frame as the camera moves, would count the AO's variation
 * across a pixel as flicker.
 */
static double track_sample(const struct synth_seq_track *t, const float *X, const float *ao,
			   const float *depth, const float *true_depth, const struct synth_pose *pose,
			   int *ok)
{
	double d[3] = { X[0] - pose->t[0], X[1] - pose->t[1], X[2] - pose->t[2] }, c[3];
	for (int k = 0; k < 3; k++) /* x_c = R^T (x_w - t) */
		c[k] = pose->R[0][k] * d[0] + pose->R[1][k] * d[1] + pose->R[2][k] * d[2];
	*ok = 0;
	if (!(c[2] > 0.0))
		return 0.0;
	const double u = t->fx * c[0] / c[2] + t->cx, v = t->fy * c[1] / c[2] + t->cy;
	if (!(u > -1.0 && v > -1.0 && u < t->width && v < t->height))
		return 0.0;
	const double x0 = floor(u), y0 = floor(v), a = u - x0, b = v - y0;
	const double wx[2] = { 1.0 - a, a }, wy[2] = { 1.0 - b, b };
	double sum = 0.0, wsum = 0.0;
	for (int dy = 0; dy < 2; dy++)
		for (int dx = 0; dx < 2; dx++) {
			const double w = wx[dx] * wy[dy];
			if (!(w > SYNTH_TRACK_MIN_WEIGHT))
				continue;
			const double x = x0 + dx, y = y0 + dy;
			if (x < 0 || y < 0 || x >= t->width || y >= t->height)
				return 0.0;
			const long q = (long)y * t->width + (long)x;
			if (!(depth[q] > 0.0f) || !(fabs(true_depth[q] - c[2]) <= SYNTH_TRACK_REL * c[2]))
				return 0.0;
			sum += w * ao[q];
			wsum += w;
		}
	*ok = 1;
	return sum / wsum;
}

void synth_seq_column_track(struct synth_seq_column *c, const struct synth_seq_track *t,
			    const float *ao, const float *depth, const float *true_depth,
			    const struct synth_pose *pose)
{
	const size_t np = (size_t)t->width * (size_t)t->height;
	if (c->offered <= c->skip) /* a frame synth_seq_column_add left out (or none yet) */
		return;
	for (size_t i = 0; i < np; i++) {
		if (isnan(t->X[3 * i]))
			continue;
		int ok;
		const double a = track_sample(t, &t->X[3 * i], ao, depth, true_depth, pose, &ok);
		if (!ok)
			continue;
		c->tsum[i] += a;
		c->tsumsq[i] += a * a;
		c->tn[i]++;
	}
}

double synth_seq_flicker_tracked(const struct synth_seq_column *c, const struct synth_seq_track *t,
				 long *count)
{
	const size_t np = (size_t)t->width * (size_t)t->height;
	double s = 0.0;
	long n = 0;
	const long frames = t->frames - c->skip;
	for (size_t i = 0; i < np && frames > 1; i++) {
		if (c->tn[i] != frames)
			continue;
		const double mean = c->tsum[i] / c->tn[i];
		const double var = c->tsumsq[i] / c->tn[i] - mean * mean;
		s += sqrt(var > 0.0 ? var : 0.0);
		n++;
	}
	if (count)
		*count = n;
	return n ? s / n : 0.0;
}
