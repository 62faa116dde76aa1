/* SPDX-License-Identifier: MIT */
/*
 * Ray tracing of the synthetic scenes: depth, true normals, and the
 * ground-truth AO that every kernel is measured against.
 *
 * AO definition (docs/accuracy.md): visibility = 1/pi * integral over the
 * hemisphere of V(w) (n.w) dw, V = 0 where a ray hits geometry within R.
 * Sampling directions with a cosine-weighted density p(w) = (n.w)/pi makes
 * the estimator the plain fraction of unblocked rays.
 */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/rng.h"
#include "synth/synth.h"

#define PI 3.14159265358979323846

/* Nearest hit of a camera ray; returns the primitive index or -1. */
static int trace(const struct synth_scene *s, vec3 o, vec3 d, double tmax, int skip, double *t,
		 vec3 *n)
{
	int hit = -1;
	double best = tmax;
	for (int i = 0; i < s->count; i++) {
		if (i == skip)
			continue;
		double tt;
		vec3 nn;
		if (synth_prim_intersect(&s->prims[i], o, d, 1e-9, best, &tt, &nn)) {
			best = tt;
			*n = nn;
			hit = i;
		}
	}
	*t = best;
	return hit;
}

int synth_trace(const struct synth_scene *s, vec3 o, vec3 d, double tmin, double tmax, double *t,
		vec3 *n)
{
	int hit = -1;
	double best = tmax;
	vec3 nn = { 0, 0, 0 };
	for (int i = 0; i < s->count; i++) {
		double tt;
		vec3 ni;
		if (synth_prim_intersect(&s->prims[i], o, d, tmin, best, &tt, &ni)) {
			best = tt;
			nn = ni;
			hit = i;
		}
	}
	*t = best;
	if (n)
		*n = nn;
	return hit;
}

int synth_occluded(const struct synth_scene *s, vec3 o, vec3 d, double tmin, double tmax)
{
	for (int i = 0; i < s->count; i++) {
		double tt;
		vec3 ni;
		if (synth_prim_intersect(&s->prims[i], o, d, tmin, tmax, &tt, &ni))
			return 1;
	}
	return 0;
}

/* Orthonormal basis around unit n (Duff et al. 2017, branchless ONB). */
static void basis(vec3 n, vec3 *b1, vec3 *b2)
{
	double sign = n.z >= 0.0 ? 1.0 : -1.0;
	double a = -1.0 / (sign + n.z);
	double b = n.x * n.y * a;
	*b1 = v3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
	*b2 = v3(b, sign + n.y * n.y * a, -n.y);
}

/* Shirley-Chiu concentric map of the unit square to the unit disk (keeps strata compact). */
static void concentric_disk(double u, double v, double *x, double *y)
{
	double a = 2.0 * u - 1.0, b = 2.0 * v - 1.0;
	if (a == 0.0 && b == 0.0) {
		*x = *y = 0.0;
		return;
	}
	double r, phi;
	if (fabs(a) > fabs(b)) {
		r = a;
		phi = (PI / 4.0) * (b / a);
	} else {
		r = b;
		phi = PI / 2.0 - (PI / 4.0) * (a / b);
	}
	*x = r * cos(phi);
	*y = r * sin(phi);
}

struct job {
	const struct synth_scene *scene;
	const struct dao_camera *cam;
	double radius;
	int rays_sqrt;
	struct synth_image *img;
	int *hit_prim;
	int band, bands;
};

static void trace_pixel_depth(const struct job *j, int x, int y)
{
	const struct dao_camera *c = j->cam;
	/* a direction with unit z component: the hit parameter is the depth z */
	vec3 d = v3((x - c->cx) / c->fx, (y - c->cy) / c->fy, 1.0);
	double t;
	vec3 n = { 0, 0, 0 };
	size_t i = (size_t)y * j->img->width + x;
	int prim = trace(j->scene, v3(0, 0, 0), d, 1e9, -1, &t, &n);
	j->hit_prim[i] = prim;
	if (prim < 0) {
		j->img->depth[i] = 0.0f;
		j->img->normal[3 * i] = 0.0f, j->img->normal[3 * i + 1] = 0.0f;
		j->img->normal[3 * i + 2] = -1.0f;
		return;
	}
	if (v3_dot(n, d) > 0.0) /* face the camera */
		n = v3_scale(n, -1.0);
	j->img->depth[i] = (float)t;
	j->img->normal[3 * i] = (float)n.x;
	j->img->normal[3 * i + 1] = (float)n.y;
	j->img->normal[3 * i + 2] = (float)n.z;
}

static float pixel_gt(const struct job *j, int x, int y)
{
	const size_t i = (size_t)y * j->img->width + x;
	const int own = j->hit_prim[i];
	if (own < 0)
		return 1.0f;
	const struct dao_camera *c = j->cam;
	const double z = j->img->depth[i];
	const vec3 X = v3((x - c->cx) / c->fx * z, (y - c->cy) / c->fy * z, z);
	const vec3 N = v3(j->img->normal[3 * i], j->img->normal[3 * i + 1], j->img->normal[3 * i + 2]);
	const double R = j->radius;

	/* candidates: primitives that come within R of X (never the surface's own solid) */
	int cand[SYNTH_MAX_PRIMS], nc = 0;
	for (int k = 0; k < j->scene->count; k++) {
		const struct synth_prim *p = &j->scene->prims[k];
		if (k == own)
			continue;
		if (p->kind == SYNTH_HALFSPACE) {
			if (v3_dot(p->n, v3_sub(X, p->c)) < R)
				cand[nc++] = k;
		} else {
			vec3 dd = v3_sub(p->bc, X);
			if (sqrt(v3_dot(dd, dd)) - p->br < R)
				cand[nc++] = k;
		}
	}
	if (nc == 0)
		return 1.0f;

	vec3 b1, b2;
	basis(N, &b1, &b2);
	const vec3 O = v3_add(X, v3_scale(N, 1e-7 * (1.0 + z)));
	uint64_t rng = 0x5eedull ^ ((uint64_t)y << 32) ^ (uint64_t)x;
	const int n = j->rays_sqrt;
	int open = 0;
	for (int a = 0; a < n; a++) {
		for (int b = 0; b < n; b++) {
			double dx, dy;
			concentric_disk((a + synth_rng_uniform(&rng)) / n, (b + synth_rng_uniform(&rng)) / n, &dx, &dy);
			double dz = sqrt(fmax(0.0, 1.0 - dx * dx - dy * dy));
			vec3 w = v3_add(v3_add(v3_scale(b1, dx), v3_scale(b2, dy)), v3_scale(N, dz));
			int blocked = 0;
			for (int k = 0; k < nc && !blocked; k++) {
				double t;
				vec3 nn;
				blocked = synth_prim_intersect(&j->scene->prims[cand[k]], O, w, 0.0, R, &t, &nn);
			}
			open += !blocked;
		}
	}
	return (float)open / (float)(n * n);
}

static void *run_depth(void *arg)
{
	const struct job *j = arg;
	for (int y = j->band; y < j->img->height; y += j->bands)
		for (int x = 0; x < j->img->width; x++)
			trace_pixel_depth(j, x, y);
	return NULL;
}

static void *run_gt(void *arg)
{
	const struct job *j = arg;
	for (int y = j->band; y < j->img->height; y += j->bands)
		for (int x = 0; x < j->img->width; x++)
			j->img->gt[(size_t)y * j->img->width + x] = pixel_gt(j, x, y);
	return NULL;
}

static void run_parallel(struct job *jobs, int threads, void *(*fn)(void *))
{
	pthread_t tid[64];
	int ok[64] = { 0 };
	for (int k = 1; k < threads; k++)
		ok[k] = pthread_create(&tid[k], NULL, fn, &jobs[k]) == 0;
	fn(&jobs[0]);
	for (int k = 1; k < threads; k++) {
		if (ok[k])
			pthread_join(tid[k], NULL);
		else
			fn(&jobs[k]); /* could not start a thread: do its band here */
	}
}

int synth_render(const struct synth_scene *scene, const struct dao_camera *cam, double radius,
		 int rays_sqrt, int threads, struct synth_image *out, struct dao_error *err)
{
	memset(out, 0, sizeof *out);
	if (threads < 1)
		threads = 1;
	if (threads > 64)
		threads = 64;
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t np = (size_t)w * h;
	out->width = w;
	out->height = h;
	out->depth = calloc(np, sizeof(float));
	out->normal = calloc(3 * np, sizeof(float));
	out->gt = calloc(np, sizeof(float));
	int *hit = calloc(np, sizeof(int));
	if (!out->depth || !out->normal || !out->gt || !hit) {
		free(hit);
		synth_image_free(out);
		return dao_error_set(err, -ENOMEM, "out of memory rendering scene '%s'", scene->name);
	}
	struct job jobs[64];
	for (int k = 0; k < threads; k++)
		jobs[k] = (struct job){ scene, cam, radius, rays_sqrt, out, hit, k, threads };
	run_parallel(jobs, threads, run_depth);
	if (rays_sqrt > 0)
		run_parallel(jobs, threads, run_gt);
	else
		for (size_t i = 0; i < np; i++)
			out->gt[i] = 1.0f;
	free(hit);
	return 0;
}

void synth_image_free(struct synth_image *img)
{
	free(img->depth);
	free(img->normal);
	free(img->gt);
	img->depth = img->normal = img->gt = NULL;
}
