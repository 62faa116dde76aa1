/* SPDX-License-Identifier: MIT */
/* Depth accuracy against the truth; see depth_accuracy.h. */
#include "synth/depth_accuracy.h"

#include <math.h>
#include <string.h>

#include "synth/linalg.h"

double depth_err_rmse(const struct depth_err *e)
{
	return e->n ? sqrt(e->sq_sum / (double)e->n) : 0.0;
}

static int is_jump(float a, float b)
{
	if ((a > 0.0f) != (b > 0.0f))
		return 1;
	if (a <= 0.0f)
		return 0;
	return fabsf(a - b) > (float)DEPTH_ACC_JUMP_REL * fminf(a, b);
}

/* Two passes of the chessboard distance transform (Rosenfeld-Pfaltz), seeded at 0. */
static void chessboard(uint8_t *d, int w, int h)
{
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			int m = d[(size_t)y * w + x];
			for (int dx = -1; dx <= 1 && y > 0; dx++)
				if (x + dx >= 0 && x + dx < w && d[(size_t)(y - 1) * w + x + dx] + 1 < m)
					m = d[(size_t)(y - 1) * w + x + dx] + 1;
			if (x > 0 && d[(size_t)y * w + x - 1] + 1 < m)
				m = d[(size_t)y * w + x - 1] + 1;
			d[(size_t)y * w + x] = (uint8_t)m;
		}
	for (int y = h - 1; y >= 0; y--)
		for (int x = w - 1; x >= 0; x--) {
			int m = d[(size_t)y * w + x];
			for (int dx = -1; dx <= 1 && y < h - 1; dx++)
				if (x + dx >= 0 && x + dx < w && d[(size_t)(y + 1) * w + x + dx] + 1 < m)
					m = d[(size_t)(y + 1) * w + x + dx] + 1;
			if (x < w - 1 && d[(size_t)y * w + x + 1] + 1 < m)
				m = d[(size_t)y * w + x + 1] + 1;
			d[(size_t)y * w + x] = (uint8_t)m;
		}
}

void depth_acc_edge_distance(const float *truth, int w, int h, uint8_t *dist)
{
	memset(dist, 255, (size_t)w * h);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			if (truth[i] <= 0.0f)
				continue;
			if ((x > 0 && is_jump(truth[i], truth[i - 1])) ||
			    (x < w - 1 && is_jump(truth[i], truth[i + 1])) ||
			    (y > 0 && is_jump(truth[i], truth[i - w])) ||
			    (y < h - 1 && is_jump(truth[i], truth[i + w])))
				dist[i] = 0;
		}
	chessboard(dist, w, h);
}

static void err_add(struct depth_err *e, double d)
{
	e->abs_sum += fabs(d);
	e->sq_sum += d * d;
	e->n++;
}

static int flying(float z, float t)
{
	return fabsf(z - t) > fmaxf((float)DEPTH_ACC_FLY_ABS, (float)DEPTH_ACC_FLY_REL * t);
}

void depth_acc_add(const float *truth, const float *raw, const float *filt, const uint8_t *dist,
		   int w, int h, struct depth_acc *acc)
{
	for (size_t i = 0; i < (size_t)w * h; i++) {
		const float t = truth[i], r = raw[i], f = filt[i];
		if (!(t > 0.0f))
			continue;
		if (!(r > 0.0f)) {
			if (f > 0.0f) {
				const int ok = fabsf(f - t) <= (float)DEPTH_ACC_FILL_TOL;
				acc->filled++;
				acc->filled_ok += ok;
				acc->filled_in += dist[i] >= DEPTH_ACC_EDGE_PX;
				acc->filled_in_ok += ok && dist[i] >= DEPTH_ACC_EDGE_PX;
			}
			continue;
		}
		if (!(f > 0.0f)) {
			acc->dropped++;
			continue;
		}
		const int ok = fabsf(f - t) <= (float)DEPTH_ACC_FILL_TOL;
		const size_t x = i % (size_t)w;
		acc->kept++;
		acc->kept_ok += ok;
		if ((x > 0 && !(raw[i - 1] > 0.0f)) || (x + 1 < (size_t)w && !(raw[i + 1] > 0.0f))) {
			acc->rim++;
			acc->rim_ok += ok;
		}
		if (dist[i] >= DEPTH_ACC_EDGE_PX) {
			err_add(&acc->raw_in, (double)r - t);
			err_add(&acc->filt_in, (double)f - t);
		} else {
			err_add(&acc->raw_edge, (double)r - t);
			err_add(&acc->filt_edge, (double)f - t);
		}
		if (dist[i] <= DEPTH_ACC_FLY_PX) {
			const int fr = flying(r, t), ff = flying(f, t);
			acc->fly_px++;
			acc->fly_raw += fr;
			acc->fly_filt += ff;
			acc->fly_created += ff && !fr;
		}
	}
}

double depth_acc_reduction(const struct depth_err *raw, const struct depth_err *filt)
{
	const double r = depth_err_mae(raw);
	return r > 0.0 ? 1.0 - depth_err_mae(filt) / r : 0.0;
}

int depth_plane_residual(const float *z, const uint8_t *mask, const struct dao_camera *cam,
			 double *rms, long *n)
{
	return depth_plane_residual_rect(z, mask, cam, 0, 0, (int)cam->width, (int)cam->height,
					 rms, n);
}

int depth_plane_residual_rect(const float *z, const uint8_t *mask, const struct dao_camera *cam,
			      int x0, int y0, int rw, int rh, double *rms, long *n)
{
	const int w = (int)cam->width;
	double m[3][3] = { { 0 } }, t[3] = { 0 }, p[3];
	long count = 0;
	for (int y = y0; y < y0 + rh; y++)
		for (int x = x0; x < x0 + rw; x++) {
			const size_t i = (size_t)y * w + x;
			if (!mask[i] || !(z[i] > 0.0f))
				continue;
			const double v[3] = { 1.0, (x - cam->cx) / cam->fx, (y - cam->cy) / cam->fy };
			for (int a = 0; a < 3; a++) {
				for (int b = 0; b < 3; b++)
					m[a][b] += v[a] * v[b];
				t[a] += v[a] / z[i];
			}
			count++;
		}
	*n = count;
	if (count < 3 || synth_solve3(m, t, p, 1e-12))
		return -1;
	double sq = 0.0;
	for (int y = y0; y < y0 + rh; y++)
		for (int x = x0; x < x0 + rw; x++) {
			const size_t i = (size_t)y * w + x;
			if (!mask[i] || !(z[i] > 0.0f))
				continue;
			const double wf = p[0] + p[1] * (x - cam->cx) / cam->fx +
					  p[2] * (y - cam->cy) / cam->fy;
			const double d = wf > 0.0 ? z[i] - 1.0 / wf : 0.0;
			sq += d * d;
		}
	*rms = sqrt(sq / (double)count);
	return 0;
}

void depth_box_mean(const float *in, float *out, int w, int h)
{
	const int r = DEPTH_BOX_SIDE / 2;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const float c = in[(size_t)y * w + x];
			float *o = &out[(size_t)y * w + x];
			*o = 0.0f;
			if (!(c > 0.0f))
				continue;
			const double tol = DEPTH_ACC_JUMP_REL * c;
			double sum = 0.0;
			int n = 0;
			for (int v = y - r; v <= y + r; v++)
				for (int u = x - r; u <= x + r; u++) {
					if (u < 0 || v < 0 || u >= w || v >= h)
						continue;
					const float d = in[(size_t)v * w + u];
					if (d > 0.0f && fabs(d - c) <= tol)
						sum += d, n++;
				}
			*o = (float)(sum / n); /* n >= 1: the pixel itself */
		}
}
