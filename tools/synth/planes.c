/* SPDX-License-Identifier: MIT */
/*
 * RANSAC planes in inverse depth (see planes.h).  Per plane: hypotheses from
 * three pixels close together (a random pixel and two within a
 * neighbourhood: on cluttered frames far more triples then lie on one
 * surface than with three random pixels), scored on a sparse grid; the best
 * is refined by least squares on its inliers with a tolerance of a few robust
 * sigmas of its own residual, three times; its region is the union of the
 * large 4-connected inlier components.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/linalg.h"
#include "synth/planes.h"
#include "synth/rng.h"
#include "synth/robust.h"

#define SCORE_STRIDE 3
#define REFINE_PASSES 3
#define CURVE_BLOCK 32        /* px: blocks of a region whose own plane ... */
#define CURVE_MAX_DEG 6.0     /* ... turns more than this (or 3 sigma of noise) from the
				 region's are not planar */
#define CURVE_CORR_PX 4.0     /* correlation length assumed for the noise of a block's fit */

void synth_plane_options_default(struct synth_plane_options *o)
{
	*o = (struct synth_plane_options){
		.max_planes = 8,
		.min_pixels = 2500,
		.iterations = 300,
		.neighbourhood = 24,
		.tolerance_w = 0.008,
		.sigmas = 3.5,
		.depth_unit = 0.0,
		.seed = 1,
	};
}

static inline double xn(const struct dao_camera *cam, double u)
{
	return (u - cam->cx) / cam->fx;
}

static inline double yn(const struct dao_camera *cam, double v)
{
	return (v - cam->cy) / cam->fy;
}

double synth_plane_w(const struct synth_plane *p, const struct dao_camera *cam, double u, double v)
{
	return p->a + p->b * xn(cam, u) + p->c * yn(cam, v);
}

/* The symmetric 3x3 system m s = t; -1 if singular relative to its scale. */
static int solve3(const double m[3][3], const double t[3], double s[3])
{
	return synth_solve3(m, t, s, 1e-12);
}

static void finish_plane(struct synth_plane *p)
{
	double len = sqrt(p->a * p->a + p->b * p->b + p->c * p->c);
	p->normal[0] = -p->b / len;
	p->normal[1] = -p->c / len;
	p->normal[2] = -p->a / len;
	p->distance = 1.0 / len;
}

/* Least squares of w on (1, x', y') over the pixels where keep[i] (or all valid if NULL). */
static int fit_pixels(const float *z, const struct dao_camera *cam, const uint8_t *keep,
		      const int32_t *labels, int32_t label, struct synth_plane *p)
{
	const int w = (int)cam->width, h = (int)cam->height;
	double m[3][3] = { { 0 } }, t[3] = { 0 };
	long n = 0;
	for (int y = 0; y < h; y++) {
		double yy = yn(cam, y);
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			if (z[i] <= 0.0f || (keep && !keep[i]) || (labels && labels[i] != label))
				continue;
			double r[3] = { 1.0, xn(cam, x), yy }, wv = 1.0 / z[i];
			for (int a = 0; a < 3; a++) {
				t[a] += r[a] * wv;
				for (int b = 0; b < 3; b++)
					m[a][b] += r[a] * r[b];
			}
			n++;
		}
	}
	double s[3];
	if (n < 3 || solve3(m, t, s))
		return -1;
	p->a = s[0], p->b = s[1], p->c = s[2];
	finish_plane(p);
	return 0;
}

int synth_plane_fit(const float *z, const struct dao_camera *cam, const int32_t *labels,
		    int32_t label, struct synth_plane *p)
{
	return fit_pixels(z, cam, NULL, labels, label, p);
}

/* Inlier tolerance at depth z: the refined one, but never below 1.5 units of the source. */
static inline double tolerance(double tol_w, double unit, double z)
{
	double floor_w = 1.5 * unit / (z * z);
	return tol_w > floor_w ? tol_w : floor_w;
}

struct finder {
	const float *z;
	const struct dao_camera *cam;
	const struct synth_plane_options *o;
	int w, h;
	uint8_t *pool;      /* 1: valid and not yet in a plane or tried */
	uint8_t *inlier;
	int32_t *queue;
	float *scratch;
	float *grid;        /* pool pixels of the scoring grid: x', y', 1/z, 1/z tolerance floor */
	long ngrid;
	int32_t *seeds;     /* pool pixels (hypothesis seeds) */
	long nseeds;
	uint64_t rng;
	double tol_w;       /* hypothesis tolerance: the options', or less on quiet frames */
};

static int hypothesis(struct finder *f, struct synth_plane *p)
{
	const int w = f->w, h = f->h, r = f->o->neighbourhood;
	int32_t idx[3];
	idx[0] = f->seeds[synth_rng_next(&f->rng) % (uint64_t)f->nseeds];
	int x0 = idx[0] % w, y0 = idx[0] / w;
	for (int k = 1; k < 3; k++) {
		int tries = 0;
		for (;;) {
			if (++tries > 32)
				return -1;
			int dx = (int)(synth_rng_next(&f->rng) % (uint64_t)(2 * r + 1)) - r;
			int dy = (int)(synth_rng_next(&f->rng) % (uint64_t)(2 * r + 1)) - r;
			int x = x0 + dx, y = y0 + dy;
			if (x < 0 || y < 0 || x >= w || y >= h || (dx == 0 && dy == 0))
				continue;
			idx[k] = y * w + x;
			if (f->pool[idx[k]] && (k == 1 || idx[k] != idx[1]))
				break;
		}
	}
	double m[3][3], t[3], s[3];
	for (int k = 0; k < 3; k++) {
		int x = idx[k] % w, y = idx[k] / w;
		m[k][0] = 1.0, m[k][1] = xn(f->cam, x), m[k][2] = yn(f->cam, y);
		t[k] = 1.0 / f->z[idx[k]];
	}
	/* not symmetric: Cramer on the rows, singular below an absolute 1e-9 */
	if (!(fabs(synth_det3(m)) > 1e-9) || synth_solve3(m, t, s, 0.0))
		return -1;
	p->a = s[0], p->b = s[1], p->c = s[2];
	return 0;
}

static long score(const struct finder *f, const struct synth_plane *p)
{
	const float a = (float)p->a, b = (float)p->b, c = (float)p->c;
	const float tol = (float)f->tol_w;
	long n = 0;
	for (long k = 0; k < f->ngrid; k++) {
		const float *g = f->grid + 4 * k;
		float r = fabsf(g[2] - (a + b * g[0] + c * g[1]));
		n += r < fmaxf(tol, g[3]);
	}
	return n;
}

/* Marks the pool pixels within the tolerance of p; returns their number. */
static long mark_inliers(struct finder *f, const struct synth_plane *p, double tol_w)
{
	long n = 0;
	for (int y = 0; y < f->h; y++)
		for (int x = 0; x < f->w; x++) {
			size_t i = (size_t)y * f->w + x;
			uint8_t in = 0;
			if (f->pool[i]) {
				double z = f->z[i];
				double r = fabs(1.0 / z - synth_plane_w(p, f->cam, x, y));
				in = r < tolerance(tol_w, f->o->depth_unit, z);
			}
			f->inlier[i] = in;
			n += in;
		}
	return n;
}

static double residual_sigma(struct finder *f, const struct synth_plane *p)
{
	size_t n = 0;
	for (int y = 0; y < f->h; y++)
		for (int x = 0; x < f->w; x++) {
			size_t i = (size_t)y * f->w + x;
			if (f->inlier[i])
				f->scratch[n++] = (float)(1.0 / f->z[i] - synth_plane_w(p, f->cam, x, y));
		}
	return synth_robust_sigma(f->scratch, n);
}

/*
 * Keeps the 4-connected components of the inliers with at least `min_px`
 * pixels: labels them `label` and takes them out of the pool.  Returns the
 * number of pixels kept.
 */
static long keep_components(struct finder *f, int32_t *labels, int32_t label, long min_px)
{
	const int w = f->w, h = f->h;
	long kept = 0;
	for (size_t s = 0; s < (size_t)w * h; s++) {
		if (f->inlier[s] != 1)
			continue;
		/* flood fill, marking visited inliers 2 */
		long head = 0, tail = 0;
		f->queue[tail++] = (int32_t)s;
		f->inlier[s] = 2;
		while (head < tail) {
			int32_t i = f->queue[head++];
			int x = i % w, y = i / w;
			const int32_t nb[4] = { x > 0 ? i - 1 : -1, x + 1 < w ? i + 1 : -1,
						y > 0 ? i - w : -1, y + 1 < h ? i + w : -1 };
			for (int k = 0; k < 4; k++)
				if (nb[k] >= 0 && f->inlier[nb[k]] == 1) {
					f->inlier[nb[k]] = 2;
					f->queue[tail++] = nb[k];
				}
		}
		if (tail < min_px)
			continue;
		for (long k = 0; k < tail; k++) {
			labels[f->queue[k]] = label;
			f->pool[f->queue[k]] = 0;
		}
		kept += tail;
	}
	return kept;
}

/*
 * A plane slanting across several surfaces (the nosings of a noisy stair)
 * collects stripes of each; the blocks of SPARSE_BLOCK px where the region
 * holds less than SPARSE_MIN of the pixels with depth are given back to the
 * pool (a plane's interior fills its blocks; its border blocks are lost too,
 * which only makes the regions more conservative).  Returns the pixels left.
 */
#define SPARSE_BLOCK 16
#define SPARSE_MIN 0.7

static long prune_sparse(struct finder *f, int32_t *labels, int32_t label)
{
	const int B = SPARSE_BLOCK;
	long left = 0;
	for (int by = 0; by < f->h; by += B)
		for (int bx = 0; bx < f->w; bx += B) {
			const int ex = bx + B < f->w ? bx + B : f->w, ey = by + B < f->h ? by + B : f->h;
			long in = 0, valid = 0;
			for (int y = by; y < ey; y++)
				for (int x = bx; x < ex; x++) {
					size_t i = (size_t)y * f->w + x;
					valid += f->z[i] > 0.0f;
					in += labels[i] == label;
				}
			if (in == 0)
				continue;
			if ((double)in >= SPARSE_MIN * (double)valid) {
				left += in;
				continue;
			}
			for (int y = by; y < ey; y++)
				for (int x = bx; x < ex; x++) {
					size_t i = (size_t)y * f->w + x;
					if (labels[i] == label) {
						labels[i] = -1;
						f->pool[i] = 1;
					}
				}
		}
	return left;
}

/*
 * A band of a curved surface passes the tolerance too (a seat, a sofa): the
 * blocks of the region whose own least-squares plane turns more than
 * CURVE_MAX_DEG from the region's plane are given back to the pool.  Far
 * away the fit of a block is noisy, so the bound grows to 3 sigma of the
 * angle that noise alone gives: for a 1/z residual sigma_w, correlated over
 * c px, a block of B px fits the slope of 1/z to sigma_w sqrt(12) f / (B
 * sqrt(N)) per unit x' with N = (B/c)^2 independent samples, i.e. a normal
 * to that times z radians.  On a banded source one step of s in 1/z inside
 * a block tilts its fit by up to about 1.5 s f / B more.  Returns the pixels
 * that remain.
 */
static long prune_curved(struct finder *f, int32_t *labels, int32_t label,
			 const struct synth_plane *p, double sigma_w)
{
	const int w = f->w, h = f->h, B = CURVE_BLOCK;
	const double deg = 3.14159265358979323846 / 180.0;
	const double noise_per_m = 3.0 * sigma_w * sqrt(12.0) * f->cam->fx / (B * B / CURVE_CORR_PX) +
				   1.5 * f->o->step_w * f->cam->fx / B;
	long left = 0;
	for (int by = 0; by < h; by += B)
		for (int bx = 0; bx < w; bx += B) {
			const int ex = bx + B < w ? bx + B : w, ey = by + B < h ? by + B : h;
			double m[3][3] = { { 0 } }, t[3] = { 0 };
			long n = 0;
			for (int y = by; y < ey; y++)
				for (int x = bx; x < ex; x++) {
					size_t i = (size_t)y * w + x;
					if (labels[i] != label)
						continue;
					double r[3] = { 1.0, xn(f->cam, x), yn(f->cam, y) }, wv = 1.0 / f->z[i];
					for (int a = 0; a < 3; a++) {
						t[a] += r[a] * wv;
						for (int b = 0; b < 3; b++)
							m[a][b] += r[a] * r[b];
					}
					n++;
				}
			if (n == 0)
				continue;
			struct synth_plane q;
			double s[3];
			int planar = 1;
			/* too few pixels to tell: judged by the block's neighbours' fate, i.e. kept */
			if (n >= B * B / 3 && !solve3(m, t, s)) {
				q.a = s[0], q.b = s[1], q.c = s[2];
				finish_plane(&q);
				double c = q.normal[0] * p->normal[0] + q.normal[1] * p->normal[1] +
					   q.normal[2] * p->normal[2];
				double bound = fmax(CURVE_MAX_DEG * deg, noise_per_m / q.a);
				planar = c >= cos(fmin(bound, 60.0 * deg));
			}
			if (planar) {
				left += n;
				continue;
			}
			for (int y = by; y < ey; y++)
				for (int x = bx; x < ex; x++) {
					size_t i = (size_t)y * w + x;
					if (labels[i] == label) {
						labels[i] = -1;
						f->pool[i] = 1;
					}
				}
		}
	return left;
}

/*
 * The frame's own noise in 1/z: the least-squares residual of 9x9 blocks
 * (grid-aligned, complete), the 25th percentile of their RMS (blocks across
 * edges and curved surfaces lie above it).  On clean renders it is the depth
 * unit's rounding; then the hypotheses use a tolerance of NOISE_SIGMAS of it
 * instead of the options', so that a plane slanting across parallel surfaces
 * (the nosings of a stair) cannot collect more inliers than each of them.
 * The refinement then widens the tolerance to o->sigmas robust sigmas of the
 * chosen plane's own residual (at most the options', unless o->tight), so
 * that the slow deviations of real planes (wavy walls) stay in their regions.
 */
#define NOISE_BLOCK 9
#define NOISE_SIGMAS 5.0

static double frame_noise_w(struct finder *f)
{
	const int B = NOISE_BLOCK;
	size_t n = 0;
	for (int by = 0; by + B <= f->h; by += B)
		for (int bx = 0; bx + B <= f->w; bx += B) {
			double m[3][3] = { { 0 } }, t[3] = { 0 }, s[3];
			int full = 1;
			for (int y = by; y < by + B && full; y++)
				for (int x = bx; x < bx + B; x++) {
					float z = f->z[(size_t)y * f->w + x];
					if (!(z > 0.0f)) {
						full = 0;
						break;
					}
					double r[3] = { 1.0, xn(f->cam, x), yn(f->cam, y) }, wv = 1.0 / z;
					for (int a = 0; a < 3; a++) {
						t[a] += r[a] * wv;
						for (int b = 0; b < 3; b++)
							m[a][b] += r[a] * r[b];
					}
				}
			if (!full || solve3(m, t, s))
				continue;
			double e2 = 0;
			for (int y = by; y < by + B; y++)
				for (int x = bx; x < bx + B; x++) {
					double r = 1.0 / f->z[(size_t)y * f->w + x] -
						   (s[0] + s[1] * xn(f->cam, x) + s[2] * yn(f->cam, y));
					e2 += r * r;
				}
			f->scratch[n++] = (float)sqrt(e2 / (B * B));
		}
	return n ? synth_select(f->scratch, n, n / 4) : 0.0;
}

static void collect_pool(struct finder *f)
{
	f->ngrid = f->nseeds = 0;
	for (int y = 0; y < f->h; y++)
		for (int x = 0; x < f->w; x++) {
			int32_t i = y * f->w + x;
			if (!f->pool[i])
				continue;
			f->seeds[f->nseeds++] = i;
			if (x % SCORE_STRIDE == 0 && y % SCORE_STRIDE == 0) {
				float *g = f->grid + 4 * f->ngrid++;
				double z = f->z[i];
				g[0] = (float)xn(f->cam, x);
				g[1] = (float)yn(f->cam, y);
				g[2] = (float)(1.0 / z);
				g[3] = (float)(1.5 * f->o->depth_unit / (z * z));
			}
		}
}

static void region_stats(struct finder *f, const int32_t *labels, int32_t label,
			 struct synth_plane *p)
{
	size_t n = 0;
	double zs = 0;
	p->zmin = INFINITY, p->zmax = 0;
	for (int y = 0; y < f->h; y++)
		for (int x = 0; x < f->w; x++) {
			size_t i = (size_t)y * f->w + x;
			if (labels[i] != label)
				continue;
			double z = f->z[i];
			f->scratch[n++] = (float)(1.0 / z - synth_plane_w(p, f->cam, x, y));
			zs += z;
			p->zmin = fmin(p->zmin, z), p->zmax = fmax(p->zmax, z);
		}
	p->pixels = (long)n;
	p->zmean = n ? zs / (double)n : 0.0;
	p->sigma_w = synth_robust_sigma(f->scratch, n);
}

int synth_planes_find(const float *z, const struct dao_camera *cam,
		      const struct synth_plane_options *o, struct synth_plane *planes, int *count,
		      int32_t *labels, struct dao_error *err)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t np = (size_t)w * h;
	*count = 0;
	if (o->max_planes < 1 || o->max_planes > SYNTH_PLANES_MAX || o->min_pixels < 3 ||
	    o->iterations < 1 || o->neighbourhood < 1 || !(o->tolerance_w > 0) || !(o->sigmas > 0))
		return dao_error_set(err, -EINVAL, "plane finder: invalid options");
	struct finder f = {
		.z = z, .cam = cam, .o = o, .w = w, .h = h,
		.pool = malloc(np), .inlier = malloc(np),
		.queue = malloc(np * sizeof(int32_t)), .scratch = malloc(np * sizeof(float)),
		.grid = malloc(np * sizeof(float)), .seeds = malloc(np * sizeof(int32_t)),
		.rng = o->seed * 0x9e3779b97f4a7c15ull + 0x5ca1ab1eull,
	};
	int r = 0;
	if (!f.pool || !f.inlier || !f.queue || !f.scratch || !f.grid || !f.seeds) {
		r = dao_error_set(err, -ENOMEM, "out of memory finding planes");
		goto out;
	}
	for (size_t i = 0; i < np; i++) {
		f.pool[i] = z[i] > 0.0f && isfinite(z[i]);
		labels[i] = -1;
	}
	f.tol_w = fmin(o->tolerance_w, fmax(NOISE_SIGMAS * frame_noise_w(&f), 1e-6));
	int failures = 0;
	while (*count < o->max_planes && failures < 4) {
		collect_pool(&f);
		if (f.nseeds < o->min_pixels || f.ngrid < 3)
			break;
		struct synth_plane best = { 0 }, p = { 0 };
		long best_score = -1;
		for (int it = 0; it < o->iterations; it++) {
			if (hypothesis(&f, &p))
				continue;
			long s = score(&f, &p);
			if (s > best_score)
				best_score = s, best = p;
		}
		if (best_score < 3) {
			failures++;
			continue;
		}
		/* refine: least squares on the inliers, tolerance from their robust sigma */
		double tol = f.tol_w;
		long n = mark_inliers(&f, &best, tol);
		for (int pass = 0; pass < REFINE_PASSES && n >= 3; pass++) {
			struct synth_plane fit = best;
			if (fit_pixels(z, cam, f.inlier, NULL, 0, &fit))
				break;
			best = fit;
			double sigma = residual_sigma(&f, &best);
			tol = fmin(o->tight ? f.tol_w : o->tolerance_w, o->sigmas * sigma);
			if (!(tol > 0))
				tol = 1e-9;
			n = mark_inliers(&f, &best, tol);
		}
		long kept = keep_components(&f, labels, *count, o->min_pixels / 4);
		if (kept >= o->min_pixels)
			kept = prune_sparse(&f, labels, *count);
		if (kept >= o->min_pixels)
			kept = prune_curved(&f, labels, *count, &best, tol / o->sigmas);
		if (kept < o->min_pixels) {
			/* not a plane of the frame: undo, and never seed from these pixels again */
			for (size_t i = 0; i < np; i++) {
				if (labels[i] == *count) {
					labels[i] = -1;
				}
				if (f.inlier[i])
					f.pool[i] = 0;
			}
			failures++;
			continue;
		}
		struct synth_plane *q = &planes[*count];
		*q = best;
		synth_plane_fit(z, cam, labels, *count, q);
		q->tolerance_w = tol;
		region_stats(&f, labels, *count, q);
		(*count)++;
		failures = 0;
	}
out:
	free(f.pool);
	free(f.inlier);
	free(f.queue);
	free(f.scratch);
	free(f.grid);
	free(f.seeds);
	return r;
}

int synth_labels_erode(int32_t *labels, int w, int h, int px)
{
	int32_t *tmp = malloc((size_t)w * h * sizeof(int32_t));
	if (!tmp)
		return -ENOMEM;
	for (int pass = 0; pass < px; pass++) {
		memcpy(tmp, labels, (size_t)w * h * sizeof(int32_t));
		for (int y = 0; y < h; y++)
			for (int x = 0; x < w; x++) {
				size_t i = (size_t)y * w + x;
				int32_t l = tmp[i];
				if (l < 0)
					continue;
				if (x == 0 || y == 0 || x == w - 1 || y == h - 1 || tmp[i - 1] != l ||
				    tmp[i + 1] != l || tmp[i - w] != l || tmp[i + w] != l)
					labels[i] = -1;
			}
	}
	free(tmp);
	return 0;
}
