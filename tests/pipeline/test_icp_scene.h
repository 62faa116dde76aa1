/* SPDX-License-Identifier: MIT */
/*
 * A scene for the camera-motion tests, rendered analytically: the inside of
 * a room (an axis-aligned box seen from within) with a box standing in it,
 * or a single flat wall; a camera pose is camera-to-world (x right, y down,
 * z forward).  Noise: sigma(z) = 0.0015 z^2 m (a structured-light sensor's),
 * rounded to millimetres.
 */
#ifndef DAO_TEST_ICP_SCENE_H
#define DAO_TEST_ICP_SCENE_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/camera.h>

#include "motion/icp.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { W = 640, H = 480 };

struct scene_fixture {
	struct dao_camera cam;
	size_t npix;
	float *z0, *z1, *inv0;
};

static inline void fixture_init(struct scene_fixture *f)
{
	struct dao_error err = {0};
	if (dao_camera_from_intrinsics(&f->cam, W, H, 525.0, 525.0, 319.5, 239.5, &err))
		abort();
	f->npix = (size_t)W * H;
	f->z0 = calloc(f->npix, sizeof(float));
	f->z1 = calloc(f->npix, sizeof(float));
	f->inv0 = calloc(f->npix, sizeof(float));
	if (!f->z0 || !f->z1 || !f->inv0)
		abort();
}

static inline void fixture_free(struct scene_fixture *f)
{
	free(f->z0);
	free(f->z1);
	free(f->inv0);
}

/* camera-to-world: R = Ry(yaw) Rx(pitch), t */
static inline void pose_from(struct dao_pose *p, double yaw_deg, double pitch_deg, double tx, double ty,
		      double tz)
{
	const double a = yaw_deg * M_PI / 180.0, b = pitch_deg * M_PI / 180.0;
	const double ry[9] = {cos(a), 0, sin(a), 0, 1, 0, -sin(a), 0, cos(a)};
	const double rx[9] = {1, 0, 0, 0, cos(b), -sin(b), 0, sin(b), cos(b)};
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			p->r[i * 3 + j] = ry[i * 3] * rx[j] + ry[i * 3 + 1] * rx[3 + j] +
					  ry[i * 3 + 2] * rx[6 + j];
	p->t[0] = tx, p->t[1] = ty, p->t[2] = tz;
}

/* the motion from the current camera to the previous one: prev^-1 cur */
static inline void relative(const struct dao_pose *prev, const struct dao_pose *cur, struct dao_pose *out)
{
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++) {
			double s = 0.0;
			for (int k = 0; k < 3; k++)
				s += prev->r[k * 3 + i] * cur->r[k * 3 + j];
			out->r[i * 3 + j] = s;
		}
		double s = 0.0;
		for (int k = 0; k < 3; k++)
			s += prev->r[k * 3 + i] * (cur->t[k] - prev->t[k]);
		out->t[i] = s;
	}
}

/* distance along d from o to the exit of the box [lo, hi] (o inside) */
static inline double box_exit(const double o[3], const double d[3], const double lo[3],
		       const double hi[3])
{
	double s = INFINITY;
	for (int k = 0; k < 3; k++) {
		if (d[k] > 0.0)
			s = fmin(s, (hi[k] - o[k]) / d[k]);
		else if (d[k] < 0.0)
			s = fmin(s, (lo[k] - o[k]) / d[k]);
	}
	return s;
}

/* distance along d from o to the entry of the box [lo, hi], or INFINITY */
static inline double box_entry(const double o[3], const double d[3], const double lo[3],
			const double hi[3])
{
	double a = 0.0, b = INFINITY;
	for (int k = 0; k < 3; k++) {
		if (d[k] == 0.0) {
			if (o[k] < lo[k] || o[k] > hi[k])
				return INFINITY;
			continue;
		}
		double s0 = (lo[k] - o[k]) / d[k], s1 = (hi[k] - o[k]) / d[k];
		if (s0 > s1) {
			const double t = s0;
			s0 = s1, s1 = t;
		}
		a = fmax(a, s0);
		b = fmin(b, s1);
	}
	return a <= b && a > 0.0 ? a : INFINITY;
}

static inline double gauss(uint64_t *st)
{
	double u[2];
	for (int k = 0; k < 2; k++) {
		*st = *st * 6364136223846793005ull + 1442695040888963407ull;
		u[k] = ((double)(*st >> 11) + 0.5) / 9007199254740992.0;
	}
	return sqrt(-2.0 * log(u[0])) * cos(2.0 * M_PI * u[1]);
}

/* depth seen by camera pose c; room: the room and its box, else a wall at z = 2 m */
static inline void render(const struct scene_fixture *f, const struct dao_pose *c, int room,
		   double noise, uint64_t seed, float *z)
{
	static const double rlo[3] = {-1.2, -1.2, -1.0}, rhi[3] = {1.3, 1.0, 3.0};
	static const double blo[3] = {-0.4, 0.3, 1.6}, bhi[3] = {0.3, 1.0, 2.3};
	static const double b2lo[3] = {0.6, -0.3, 2.2}, b2hi[3] = {1.1, 0.2, 2.6};
	uint64_t st = seed * 0x9E3779B97F4A7C15ull + 1u;
	for (int v = 0; v < H; v++)
		for (int u = 0; u < W; u++) {
			double dc[3], d[3];
			dao_camera_pixel_to_view(&f->cam, u, v, 1.0, dc);
			for (int i = 0; i < 3; i++)
				d[i] = c->r[i * 3] * dc[0] + c->r[i * 3 + 1] * dc[1] +
				       c->r[i * 3 + 2] * dc[2];
			double s;
			if (room) {
				s = box_exit(c->t, d, rlo, rhi);
				s = fmin(s, box_entry(c->t, d, blo, bhi));
				s = fmin(s, box_entry(c->t, d, b2lo, b2hi));
			} else {
				s = d[2] > 0.0 ? (2.0 - c->t[2]) / d[2] : 0.0;
			}
			/* s is the view z: the ray's z in the camera is 1 */
			if (noise > 0.0) {
				s += noise * 0.0015 * s * s * gauss(&st);
				s = floor(s * 1000.0 + 0.5) / 1000.0;
			}
			z[(size_t)v * W + (size_t)u] = s > 0.0 && s < 10.0 ? (float)s : 0.0f;
		}
}

/* ICP's two frames: the previous one (pose prev, noise0, seed0) into z0 and
 * its inverse depth into inv0, the current one (cur, noise1, seed1) into z1 */
static inline void render_pair(const struct scene_fixture *f, const struct dao_pose *prev,
			       const struct dao_pose *cur, int room, double noise0,
			       uint64_t seed0, double noise1, uint64_t seed1)
{
	render(f, prev, room, noise0, seed0, f->z0);
	render(f, cur, room, noise1, seed1, f->z1);
	for (size_t i = 0; i < f->npix; i++)
		f->inv0[i] = f->z0[i] > 0.0f ? 1.0f / f->z0[i] : 0.0f;
}

#endif
