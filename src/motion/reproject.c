/* SPDX-License-Identifier: MIT */
#include <stddef.h>
#include <string.h>

#include "motion/reproject.h"
#include "motion/reproject_px.h"
#include "core/threadpool.h"

size_t dao_history_reproject_scratch(int w, int h)
{
	return 2 * (size_t)w * (size_t)h + 2 * (size_t)h;
}

void dao_reproject_land_ref(const struct dao_reproject_land *s, int y0, int y1)
{
	const int w = s->w;
	const float dg[3] = {s->R[0] * s->ax, s->R[3] * s->ax, s->R[6] * s->ax};
	for (int y = y0; y < y1; y++) {
		float g0[3];
		dao_reproject_row_g0(s, y, g0);
		int32_t lo = s->h, hi = -1;
		dao_reproject_px_span(s, g0, dg, 0, w, (size_t)y * (size_t)w, &lo, &hi);
		s->rows[2 * y] = lo;
		s->rows[2 * y + 1] = hi;
	}
}

struct reproject_job {
	const struct dao_reproject_land *l;
	dao_reproject_land_fn land;
	const uint8_t *count, *age;
	float *hist_out;
	uint8_t *count_out, *age_out;
};

static void land_rows(void *arg, int y0, int y1)
{
	const struct reproject_job *j = arg;
	j->land(j->l, y0, y1);
}

/* output rows [y0, y1): cleared, then every source pixel landing there, in
 * row order, the nearer winning (on a tie the first) */
static void splat_rows(void *arg, int y0, int y1)
{
	const struct reproject_job *j = arg;
	const struct dao_reproject_land *l = j->l;
	const size_t w = (size_t)l->w, o0 = (size_t)y0 * w, n = (size_t)(y1 - y0) * w;
	/* locals: the byte stores below could alias the job's pointers */
	const int32_t *dest = l->dest, *rows = l->rows;
	const float *zinv = l->zinv;
	const uint8_t *count = j->count, *age = j->age;
	float *hist_out = j->hist_out + o0;
	uint8_t *count_out = j->count_out + o0, *age_out = j->age_out + o0;
	const int h = l->h;
	memset(hist_out, 0, n * sizeof(float));
	memset(count_out, 0, n);
	memset(age_out, 255, n);
	for (int sy = 0; sy < h; sy++) {
		if (rows[2 * sy + 1] < y0 || rows[2 * sy] >= y1)
			continue;
		const size_t row = (size_t)sy * w;
		for (size_t i = row; i < row + w; i++) {
			/* -1 and the other bands' pixels wrap to n or more */
			const size_t o = (size_t)(int64_t)dest[i] - o0;
			if (o >= n)
				continue;
			/* a landed 1/z is >= 0 (never NaN) and an empty pixel holds
			 * 0: the depth test decides but for a 1/z of 0 (an underflow) */
			const float iz = zinv[i];
			if (!(iz > hist_out[o]) && count_out[o])
				continue;
			hist_out[o] = iz;
			count_out[o] = count[i];
			age_out[o] = age[i];
		}
	}
}

static void run_rows(struct dao_pool *pool, int rows, int min_rows, dao_pool_fn fn, void *arg)
{
	if (pool)
		dao_pool_run(pool, rows, min_rows, fn, arg);
	else
		fn(arg, 0, rows);
}

void dao_history_reproject(const struct dao_camera *cam, const struct dao_pose *cur_to_prev,
			   const float *hist, const uint8_t *count, const uint8_t *age,
			   float *hist_out, uint8_t *count_out, uint8_t *age_out, int32_t *scratch,
			   dao_reproject_land_fn land, struct dao_pool *pool)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t npix = (size_t)w * (size_t)h;
	struct dao_reproject_land l = {
		.hist = hist, .count = count, .dest = scratch, .zinv = (float *)(scratch + npix),
		.rows = scratch + 2 * npix, .w = w, .h = h,
		.ax = cam->ax, .bx = cam->bx, .ay = cam->ay, .by = cam->by,
	};
	/* prev -> cur: R^T, -R^T t */
	const double *r = cur_to_prev->r, *t = cur_to_prev->t;
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			l.R[i * 3 + j] = (float)r[j * 3 + i];
		l.T[i] = (float)-(r[i] * t[0] + r[3 + i] * t[1] + r[6 + i] * t[2]);
	}
	l.inv_ax = 1.0f / cam->ax, l.inv_ay = 1.0f / cam->ay;
	l.ub = cam->bx * l.inv_ax, l.vb = cam->by * l.inv_ay;
	struct reproject_job j = {
		.l = &l, .land = land ? land : dao_reproject_land_ref, .count = count, .age = age,
		.hist_out = hist_out, .count_out = count_out, .age_out = age_out,
	};
	/* where every pixel lands, then the splat by output bands */
	run_rows(pool, h, 8, land_rows, &j);
	run_rows(pool, h, 8, splat_rows, &j);
}
