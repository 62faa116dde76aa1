/* SPDX-License-Identifier: MIT */
/*
 * For each plane, the points of the frame more than a tolerance in front of
 * it (the camera side, where n.X + distance > 0) that form a surface (they
 * survive a 3x3 opening; the plane's own outliers do not) are the
 * occluders.  What lies behind their visible surface is unknown (the back
 * of a sphere reaches a floor point that its front does not), so each
 * occluder stands for a segment THICKNESS deep along its viewing ray,
 * sampled at 3 points.  They are put into a grid of cells of radius / 2; each region pixel then looks at
 * the candidates of the cells its radius-ball touches, block by block (8x8
 * px: a block whose ball, grown by the block's own size, meets no candidate
 * is open as a whole).
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/open_planes.h"
#include "synth/sensor_stats.h"

#define BLOCK 8
#define MIN_TOLERANCE 0.02   /* m */
#define SIGMAS 4.0
#define THICKNESS 0.3        /* m: what the camera cannot see behind an occluder's surface */
#define MAX_CELLS (1 << 22)

static int find_planes(const float *z, const struct dao_camera *cam, double depth_unit, int tight,
		       struct synth_plane *planes, int *count, int32_t *labels, struct dao_error *err)
{
	struct synth_plane_options po;
	synth_plane_options_default(&po);
	po.depth_unit = depth_unit;
	po.tight = tight;
	double band_c = 0;
	if (synth_band_constant(z, (int)cam->width, (int)cam->height, depth_unit, &band_c))
		return dao_error_set(err, -ENOMEM, "out of memory finding planes");
	po.step_w = band_c > 0 ? 1.0 / band_c : 0.0;
	return synth_planes_find(z, cam, &po, planes, count, labels, err);
}

int synth_planes_find_frame(const float *z, const struct dao_camera *cam, double depth_unit,
			    struct synth_plane *planes, int *count, int32_t *labels,
			    struct dao_error *err)
{
	return find_planes(z, cam, depth_unit, 0, planes, count, labels, err);
}

#define SAMPLES 3            /* along each occluder's depth */
#define MIN_AREA 400         /* px: smaller open fragments are dropped (they are what is left
				of planes slanting across several surfaces, not open floor) */

struct grid {
	double x0, y0, z0, cell;
	int nx, ny, nz;
	int32_t *start;    /* nx ny nz + 1 offsets into pts */
	float *pts;        /* occluder samples (x, y, z), ordered by cell */
	int32_t *queue;    /* scratch */
	float *samples;    /* SAMPLES points per pixel: its point, then deeper along its ray */
};

static long cell_of(const struct grid *g, const float *P)
{
	int ix = (int)floor((P[0] - g->x0) / g->cell), iy = (int)floor((P[1] - g->y0) / g->cell);
	int iz = (int)floor((P[2] - g->z0) / g->cell);
	if (ix < 0 || iy < 0 || iz < 0 || ix >= g->nx || iy >= g->ny || iz >= g->nz)
		return -1;
	return ((long)iz * g->ny + iy) * g->nx + ix;
}

/*
 * Counting sort of the occluders' samples into their cells, copied in cell
 * order.  Occluders are taken on every other row and column: a surface is
 * still covered to a pixel's footprint, far below the radius.
 */
static void grid_build(struct grid *g, const uint8_t *cand, int w, int h)
{
	const long ncell = (long)g->nx * g->ny * g->nz;
	memset(g->start, 0, (size_t)(ncell + 1) * sizeof(int32_t));
	for (int pass = 0; pass < 2; pass++) {
		for (int y = 0; y < h; y += 2)
			for (int x = 0; x < w; x += 2) {
				size_t i = (size_t)y * w + x;
				if (!cand[i])
					continue;
				for (int k = 0; k < SAMPLES; k++) {
					const float *P = g->samples + 3 * (i * SAMPLES + (size_t)k);
					long c = cell_of(g, P);
					if (c < 0)
						continue;
					if (pass == 0) {
						g->start[c + 1]++;
					} else {
						float *q = g->pts + 3 * (size_t)g->queue[c]++;
						q[0] = P[0], q[1] = P[1], q[2] = P[2];
					}
				}
			}
		if (pass == 0) {
			for (long c = 0; c < ncell; c++)
				g->start[c + 1] += g->start[c];
			memcpy(g->queue, g->start, (size_t)ncell * sizeof(int32_t));
		}
	}
}

/* 1 if an occluder sample lies within r of C (cells farther than r skipped). */
static int any_within(const struct grid *g, const double *C, double r)
{
	int lo[3], hi[3];
	const double o[3] = { g->x0, g->y0, g->z0 };
	const int n[3] = { g->nx, g->ny, g->nz };
	for (int a = 0; a < 3; a++) {
		lo[a] = (int)floor((C[a] - r - o[a]) / g->cell);
		hi[a] = (int)floor((C[a] + r - o[a]) / g->cell);
		if (lo[a] < 0)
			lo[a] = 0;
		if (hi[a] > n[a] - 1)
			hi[a] = n[a] - 1;
		if (lo[a] > hi[a])
			return 0;
	}
	const double r2 = r * r;
	for (int iz = lo[2]; iz <= hi[2]; iz++) {
		double dz = fmax(0.0, fmax(o[2] + iz * g->cell - C[2], C[2] - (o[2] + (iz + 1) * g->cell)));
		for (int iy = lo[1]; iy <= hi[1]; iy++) {
			double dy = fmax(0.0, fmax(o[1] + iy * g->cell - C[1], C[1] - (o[1] + (iy + 1) * g->cell)));
			for (int ix = lo[0]; ix <= hi[0]; ix++) {
				double dx = fmax(0.0, fmax(o[0] + ix * g->cell - C[0],
							   C[0] - (o[0] + (ix + 1) * g->cell)));
				if (dx * dx + dy * dy + dz * dz >= r2)
					continue; /* the cell lies outside the ball */
				long c = ((long)iz * g->ny + iy) * g->nx + ix;
				const float *P = g->pts + 3 * (size_t)g->start[c], *end = g->pts + 3 * (size_t)g->start[c + 1];
				for (; P < end; P += 3) {
					double ex = P[0] - C[0], ey = P[1] - C[1], ez = P[2] - C[2];
					if (ex * ex + ey * ey + ez * ez < r2)
						return 1;
				}
			}
		}
	}
	return 0;
}

/*
 * Each pixel's view-space point into pts (0 where there is no depth), its
 * occluder samples (the point and two deeper along its ray) into
 * g->samples, and the bounding box of the points with depth and of their
 * samples.
 */
static void points_and_samples(const float *z, const struct dao_camera *cam, float *pts,
			       struct grid *g, double lo[3], double hi[3])
{
	const int w = (int)cam->width, h = (int)cam->height;
	for (int a = 0; a < 3; a++)
		lo[a] = INFINITY, hi[a] = -INFINITY;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			double P[3] = { 0, 0, 0 };
			if (z[i] > 0) {
				dao_camera_pixel_to_view(cam, x, y, z[i], P);
				for (int a = 0; a < 3; a++)
					lo[a] = fmin(lo[a], P[a]), hi[a] = fmax(hi[a], P[a]);
			}
			for (int a = 0; a < 3; a++)
				pts[3 * i + a] = (float)P[a];
			const double len = sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
			for (int k = 0; k < SAMPLES; k++) {
				const double t = len > 0 ? 1.0 + THICKNESS * k / (SAMPLES - 1) / len : 1.0;
				for (int a = 0; a < 3; a++) {
					double v = P[a] * t;
					g->samples[(SAMPLES * i + (size_t)k) * 3 + (size_t)a] = (float)v;
					if (z[i] > 0)
						lo[a] = fmin(lo[a], v), hi[a] = fmax(hi[a], v);
				}
			}
		}
}

/* The grid over the box lo..hi: cells of radius / 2, doubled until at most MAX_CELLS. */
static int grid_alloc(struct grid *g, const double lo[3], const double hi[3], double radius,
		      struct dao_error *err)
{
	g->cell = radius / 2;
	for (;;) {
		g->nx = (int)((hi[0] - lo[0]) / g->cell) + 1;
		g->ny = (int)((hi[1] - lo[1]) / g->cell) + 1;
		g->nz = (int)((hi[2] - lo[2]) / g->cell) + 1;
		if ((double)g->nx * g->ny * g->nz <= MAX_CELLS)
			break;
		g->cell *= 2;
	}
	g->x0 = lo[0], g->y0 = lo[1], g->z0 = lo[2];
	g->start = malloc(((size_t)g->nx * g->ny * g->nz + 1) * sizeof(int32_t));
	g->queue = malloc(((size_t)g->nx * g->ny * g->nz + 1) * sizeof(int32_t));
	if (!g->start || !g->queue)
		return dao_error_set(err, -ENOMEM, "out of memory finding open planes");
	return 0;
}

/* cand[i] = 1 where the point is in front of the plane by more than the tolerance. */
static void occluders_in_front(const float *z, const float *pts, const int32_t *lab, size_t np,
			       const struct synth_plane *pl, int p, uint8_t *cand)
{
	const double *n = pl->normal;
	for (size_t i = 0; i < np; i++) {
		cand[i] = 0;
		if (!(z[i] > 0) || lab[i] == p)
			continue;
		const float *P = pts + 3 * i;
		double above = n[0] * P[0] + n[1] * P[1] + n[2] * P[2] + pl->distance;
		double zz = P[2], tol = fmax(MIN_TOLERANCE, SIGMAS * pl->sigma_w * zz * zz);
		cand[i] = above > tol;
	}
}

/*
 * The plane's own noise is not an occluder: a morphological opening
 * (3x3 erosion, then dilation) keeps surfaces and drops isolated
 * outliers and the thin row patterns some sensors leave on planes.
 */
static void open_occluders(uint8_t *cand, int w, int h)
{
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			int all = cand[i] && x > 0 && y > 0 && x < w - 1 && y < h - 1;
			for (int k = -1; all && k <= 1; k++)
				all = (cand[i + (size_t)((long)k * w) - 1] & 1) &&
				      (cand[i + (size_t)((long)k * w)] & 1) &&
				      (cand[i + (size_t)((long)k * w) + 1] & 1);
			if (all)
				cand[i] |= 2;   /* survives the erosion */
		}
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			int any = 0;
			for (int yy = y - 1; yy <= y + 1 && !any; yy++)
				for (int xx = x - 1; xx <= x + 1 && !any; xx++)
					any = xx >= 0 && yy >= 0 && xx < w && yy < h &&
					      (cand[(size_t)yy * w + xx] & 2);
			if (any && (cand[i] & 1))
				cand[i] |= 4;   /* in the opening */
		}
	for (size_t i = 0; i < (size_t)w * h; i++)
		cand[i] = (cand[i] & 4) != 0;
}

/* The pixels of plane p in the block at (bx, by) with no occluder within the radius. */
static void mark_open_block(const struct grid *g, const float *pts, const int32_t *lab, int p,
			    int bx, int by, int w, int h, double radius, uint8_t *mask, long *count)
{
	/* the block's pixels of this plane: their centre and extent */
	double C[3] = { 0, 0, 0 }, ext = 0;
	int nb = 0;
	for (int y = by; y < by + BLOCK && y < h; y++)
		for (int x = bx; x < bx + BLOCK && x < w; x++) {
			size_t i = (size_t)y * w + x;
			if (lab[i] != p)
				continue;
			for (int a = 0; a < 3; a++)
				C[a] += pts[3 * i + a];
			nb++;
		}
	if (!nb)
		return;
	for (int a = 0; a < 3; a++)
		C[a] /= nb;
	for (int y = by; y < by + BLOCK && y < h; y++)
		for (int x = bx; x < bx + BLOCK && x < w; x++) {
			size_t i = (size_t)y * w + x;
			if (lab[i] != p)
				continue;
			const float *P = pts + 3 * i;
			double dx = P[0] - C[0], dy = P[1] - C[1], dz = P[2] - C[2];
			ext = fmax(ext, sqrt(dx * dx + dy * dy + dz * dz));
		}
	const int whole = !any_within(g, C, radius + ext);
	for (int y = by; y < by + BLOCK && y < h; y++)
		for (int x = bx; x < bx + BLOCK && x < w; x++) {
			size_t i = (size_t)y * w + x;
			if (lab[i] != p)
				continue;
			double Pi[3] = { pts[3 * i], pts[3 * i + 1], pts[3 * i + 2] };
			if (whole || !any_within(g, Pi, radius)) {
				mask[i] = 1;
				(*count)++;
			}
		}
}

/*
 * Drops the fragments, the 4-connected components of the mask below MIN_AREA
 * (queue: np entries of scratch), and counts what is left.
 */
static long drop_small_fragments(uint8_t *mask, int w, int h, int32_t *queue)
{
	const size_t np = (size_t)w * h;
	for (size_t s0 = 0; s0 < np; s0++) {
		if (mask[s0] != 1)
			continue;
		long head = 0, tail = 0;
		queue[tail++] = (int32_t)s0;
		mask[s0] = 2;
		while (head < tail) {
			int32_t i = queue[head++];
			int x = i % w, y = i / w;
			const int32_t nb[4] = { x > 0 ? i - 1 : -1, x + 1 < w ? i + 1 : -1,
						y > 0 ? i - w : -1, y + 1 < h ? i + w : -1 };
			for (int k = 0; k < 4; k++)
				if (nb[k] >= 0 && mask[nb[k]] == 1) {
					mask[nb[k]] = 2;
					queue[tail++] = nb[k];
				}
		}
		if (tail < MIN_AREA)
			for (long k = 0; k < tail; k++)
				mask[queue[k]] = 3;
	}
	long count = 0;
	for (size_t i = 0; i < np; i++) {
		mask[i] = mask[i] == 2;
		count += mask[i];
	}
	return count;
}

int synth_open_planes(const float *z, const struct dao_camera *cam, double depth_unit,
		      double radius, uint8_t *mask, long *count, struct dao_error *err)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t np = (size_t)w * h;
	struct synth_plane planes[SYNTH_PLANES_MAX];
	int nplanes = 0, ret = 0;
	struct grid g = { 0 };
	int32_t *lab = malloc(np * sizeof(int32_t));
	float *pts = malloc(3 * np * sizeof(float));
	uint8_t *cand = malloc(np);
	g.pts = malloc(np * SAMPLES * 3 * sizeof(float));
	g.samples = malloc(np * SAMPLES * 3 * sizeof(float));
	memset(mask, 0, np);
	*count = 0;
	if (!lab || !pts || !cand || !g.pts || !g.samples) {
		ret = dao_error_set(err, -ENOMEM, "out of memory finding open planes");
		goto out;
	}
	/* tight planes: a pixel wrongly taken as open would count against the AO */
	if ((ret = find_planes(z, cam, depth_unit, 1, planes, &nplanes, lab, err)))
		goto out;
	if (synth_labels_erode(lab, w, h, SYNTH_STATS_ERODE)) {
		ret = dao_error_set(err, -ENOMEM, "out of memory finding open planes");
		goto out;
	}
	double lo[3], hi[3];
	points_and_samples(z, cam, pts, &g, lo, hi);
	if (!(hi[2] > 0))
		goto out;
	if ((ret = grid_alloc(&g, lo, hi, radius, err)))
		goto out;
	for (int p = 0; p < nplanes; p++) {
		occluders_in_front(z, pts, lab, np, &planes[p], p, cand);
		open_occluders(cand, w, h);
		grid_build(&g, cand, w, h);
		for (int by = 0; by < h; by += BLOCK)
			for (int bx = 0; bx < w; bx += BLOCK)
				mark_open_block(&g, pts, lab, p, bx, by, w, h, radius, mask, count);
	}
	/* g.samples is free by now: 9 np floats for the fragments' queue */
	*count = drop_small_fragments(mask, w, h, (int32_t *)g.samples);
out:
	free(lab);
	free(pts);
	free(cand);
	free(g.pts);
	free(g.samples);
	free(g.start);
	free(g.queue);
	return ret;
}
