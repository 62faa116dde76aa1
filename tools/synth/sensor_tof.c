/* SPDX-License-Identifier: MIT */
/*
 * Continuous-wave time of flight (Kinect v2 / Azure Kinect class).
 *
 * The camera floods the scene with light modulated at TOF_FREQ and measures,
 * per pixel, the phase of the returning modulation: the phase of the sum of
 * everything the pixel receives, as phasors a e^(i 2 pi f L / c) of amplitude
 * a and path length L (2 r for the direct return).  Kinect v2 measures at
 * three frequencies up to 80 MHz and uses the lower ones only to unwrap the
 * phase; the model takes the 80 MHz phase, unwrapped to the period nearest
 * the true distance.  What the model does and what it produces:
 *
 *  1. Flying pixels: a pixel across a depth edge receives light from both
 *     surfaces.  Where the render's depth jumps by more than TOF_EDGE_JUMP
 *     between neighbours, the pixel is traced with TOF_SUB^2 sub-rays and
 *     their phasors summed: the measured distance lies between foreground
 *     and background, weighted by what each contributes.
 *  2. Multipath: light reaching the point via another surface travels
 *     farther.  From each point TOF_MP_RAYS cosine-weighted rays find the
 *     surfaces that light it indirectly; each contributes (albedo / K)
 *     cos(theta_Y) / |Y|^2 relative to the direct cos(theta_X) / |X|^2 (a
 *     Lambertian bounce under the camera's own illumination; Fuchs 2010,
 *     Jimenez et al. 2014), at path |Y| + |Y - X| + |X|, if Y lies in the
 *     illuminated field (the camera's) and is lit.  The sum biases the
 *     distance upward, most in concave corners (longer detours partly cancel
 *     at 80 MHz).  Computed every TOF_MP_STEP px and interpolated.
 *  3. Noise: shot noise, so the phase noise falls as 1/sqrt(amplitude): the
 *     distance noise is TOF_NOISE_1M at 1 m on a surface facing the camera
 *     and grows as r / sqrt(cos(incidence)) (Kinect v2: about 1.5 mm at 1 m
 *     to 5 mm at 4 m); independent per pixel.  Pixels whose amplitude is
 *     below TOF_MIN_AMPLITUDE (far, dark, grazing) have no data.
 * The distance along the ray then gives z; depth in 1 mm units.
 */
#include <complex.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/parallel.h"
#include "synth/sensor.h"
#include "synth/sensor_field.h"

#define TOF_FREQ 80e6            /* Hz: the phase wraps every c / (2 f) = 1.87 m */
#define TOF_LIGHT_SPEED 299792458.0
#define TOF_ALBEDO 0.8
#define TOF_EDGE_JUMP 0.02       /* relative depth jump that marks an edge pixel */
#define TOF_SUB 4                /* sub-rays per axis on edge pixels */
#define TOF_MP_RAYS 32
#define TOF_MP_STEP 4            /* px between multipath samples */
#define TOF_MP_RANGE 3.0         /* m: farther surfaces light too little to count */
#define TOF_NOISE_1M 0.0012      /* m, distance noise at 1 m facing the camera */
#define TOF_MIN_AMPLITUDE 0.01   /* albedo cos / r^2 (r in m) below which there is no data */

#define PI 3.14159265358979323846

static inline double complex phasor(double amplitude, double path)
{
	return amplitude * cexp(I * 2.0 * PI * TOF_FREQ * path / TOF_LIGHT_SPEED);
}

struct tof_job {
	const struct synth_scene *scene;
	const struct dao_camera *cam;
	const struct synth_image *img;
	uint64_t seed;
	int mw, mh;                  /* multipath grid */
	double complex *mp;          /* indirect / direct, per grid point */
	double complex *direct;      /* per pixel: the direct phasor (sum over sub-rays) */
};

static vec3 pixel_ray(const struct dao_camera *c, double x, double y)
{
	return v3((x - c->cx) / c->fx, (y - c->cy) / c->fy, 1.0);
}

/* Direct return of the ray through (x, y): amplitude and path phasor; 0 if nothing. */
static double complex direct_return(const struct tof_job *j, double x, double y)
{
	const vec3 d = pixel_ray(j->cam, x, y);
	double t;
	vec3 n;
	if (synth_trace(j->scene, v3(0, 0, 0), d, 1e-9, 1e9, &t, &n) < 0)
		return 0.0;
	const double r = t * sqrt(v3_dot(d, d));
	const double cos_in = fabs(v3_dot(n, d)) / sqrt(v3_dot(d, d));
	return phasor(TOF_ALBEDO * cos_in / (r * r), 2.0 * r);
}

static void direct_band(void *ctx, int band, int y0, int y1)
{
	(void)band;
	struct tof_job *j = ctx;
	const struct dao_camera *c = j->cam;
	const int w = (int)c->width, h = (int)c->height;
	const float *z = j->img->depth;
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			int edge = 0;
			const float zc = z[i];
			for (int k = 0; k < 4 && !edge; k++) {
				int xx = x + (k == 0) - (k == 1), yy = y + (k == 2) - (k == 3);
				if (xx < 0 || yy < 0 || xx >= w || yy >= h)
					continue;
				float zn = z[(size_t)yy * w + xx];
				edge = (zn > 0) != (zc > 0) || fabsf(zn - zc) > TOF_EDGE_JUMP * fminf(zn, zc);
			}
			if (!edge) {
				if (zc <= 0) {
					j->direct[i] = 0.0;
					continue;
				}
				const vec3 d = pixel_ray(c, x, y);
				const double r = zc * sqrt(v3_dot(d, d));
				const vec3 n = v3(j->img->normal[3 * i], j->img->normal[3 * i + 1],
						  j->img->normal[3 * i + 2]);
				const double cos_in = fabs(v3_dot(n, d)) / sqrt(v3_dot(d, d));
				j->direct[i] = phasor(TOF_ALBEDO * cos_in / (r * r), 2.0 * r);
				continue;
			}
			double complex sum = 0.0;
			for (int sy = 0; sy < TOF_SUB; sy++)
				for (int sx = 0; sx < TOF_SUB; sx++)
					sum += direct_return(j, x - 0.5 + (sx + 0.5) / TOF_SUB,
							     y - 0.5 + (sy + 0.5) / TOF_SUB);
			j->direct[i] = sum / (TOF_SUB * TOF_SUB);
		}
}

/* Orthonormal basis around unit n (Duff et al. 2017). */
static void basis(vec3 n, vec3 *b1, vec3 *b2)
{
	double sign = n.z >= 0.0 ? 1.0 : -1.0;
	double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
	*b1 = v3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
	*b2 = v3(b, sign + n.y * n.y * a, -n.y);
}

/* Indirect light of the point seen at (x, y), relative to its direct light (step 2). */
static double complex multipath(const struct tof_job *j, int x, int y)
{
	const struct dao_camera *c = j->cam;
	const size_t i = (size_t)y * c->width + x;
	const double z = j->img->depth[i];
	if (z <= 0)
		return 0.0;
	const vec3 X = v3_scale(pixel_ray(c, x, y), z);
	const vec3 N = v3(j->img->normal[3 * i], j->img->normal[3 * i + 1], j->img->normal[3 * i + 2]);
	const double rx = sqrt(v3_dot(X, X)), cos_x = -v3_dot(N, X) / rx;
	if (cos_x <= 0.05)
		return 0.0;
	vec3 b1, b2;
	basis(N, &b1, &b2);
	const vec3 O = v3_add(X, v3_scale(N, 1e-6 * (1.0 + z)));
	uint64_t rng = synth_pixel_rng(j->seed, 5, i);
	double complex sum = 0.0;
	const int n = (int)sqrt((double)TOF_MP_RAYS);
	for (int a = 0; a < n; a++)
		for (int b = 0; b < n; b++) {
			/* cosine-weighted, stratified */
			double u1 = (a + synth_rng_uniform(&rng)) / n, u2 = (b + synth_rng_uniform(&rng)) / n;
			double rr = sqrt(u1), phi = 2.0 * PI * u2;
			vec3 wv = v3_add(v3_add(v3_scale(b1, rr * cos(phi)), v3_scale(b2, rr * sin(phi))),
					 v3_scale(N, sqrt(fmax(0.0, 1.0 - u1))));
			double t;
			vec3 ny;
			if (synth_trace(j->scene, O, wv, 1e-9, TOF_MP_RANGE, &t, &ny) < 0)
				continue;
			const vec3 Y = v3_add(O, v3_scale(wv, t));
			const double ry = sqrt(v3_dot(Y, Y));
			if (v3_dot(ny, Y) > 0.0)
				ny = v3_scale(ny, -1.0); /* the side the camera could light */
			const double cos_y = -v3_dot(ny, Y) / ry;
			/*
			 * Y must be lit: inside the illuminated field (the camera's own),
			 * facing the camera with nothing in between; and face X.
			 */
			if (Y.z <= 0.0 || cos_y <= 0.0 || v3_dot(ny, wv) >= 0.0)
				continue;
			const double uy = c->fx * Y.x / Y.z + c->cx, vy = c->fy * Y.y / Y.z + c->cy;
			if (uy < -0.5 || vy < -0.5 || uy > c->width - 0.5 || vy > c->height - 0.5 ||
			    synth_occluded(j->scene, v3(0, 0, 0), Y, 1e-9, 1.0 - 1e-6))
				continue;
			sum += phasor(cos_y / (ry * ry), ry + t + rx);
		}
	/* relative to the direct light: (albedo / K) sum / (cos_x / rx^2), as phasors */
	const double complex direct = phasor(cos_x / (rx * rx), 2.0 * rx);
	return TOF_ALBEDO / (n * n) * sum / direct;
}

static void multipath_band(void *ctx, int band, int y0, int y1)
{
	(void)band;
	struct tof_job *j = ctx;
	for (int gy = y0; gy < y1; gy++)
		for (int gx = 0; gx < j->mw; gx++) {
			int x = gx * TOF_MP_STEP, y = gy * TOF_MP_STEP;
			if (x >= (int)j->cam->width)
				x = (int)j->cam->width - 1;
			if (y >= (int)j->cam->height)
				y = (int)j->cam->height - 1;
			j->mp[(size_t)gy * j->mw + gx] = multipath(j, x, y);
		}
}

int synth_sensor_tof(const struct synth_scene *scene, const struct dao_camera *cam,
		     const struct synth_image *img, uint64_t seed, int threads, float *out,
		     struct dao_error *err)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t np = (size_t)w * h;
	struct tof_job j = { scene, cam, img, seed, (w - 1) / TOF_MP_STEP + 2,
			     (h - 1) / TOF_MP_STEP + 2, NULL, NULL };
	j.mp = malloc((size_t)j.mw * j.mh * sizeof(double complex));
	j.direct = malloc(np * sizeof(double complex));
	if (!j.mp || !j.direct) {
		free(j.mp);
		free(j.direct);
		return dao_error_set(err, -ENOMEM, "time of flight: out of memory");
	}
	synth_parallel_rows(h, threads, 1, direct_band, &j);
	synth_parallel_rows(j.mh, threads, 1, multipath_band, &j);
	const double wrap = TOF_LIGHT_SPEED / (2.0 * TOF_FREQ);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			const double complex dir = j.direct[i];
			const double amp = cabs(dir);
			out[i] = 0.0f;
			if (amp <= 0.0 || img->depth[i] <= 0.0f)
				continue;
			/* the multipath ratio, bilinear between grid points */
			const double fx = (double)x / TOF_MP_STEP, fy = (double)y / TOF_MP_STEP;
			const int gx = (int)fx, gy = (int)fy;
			const double tx = fx - gx, ty = fy - gy;
			const double complex *g = j.mp + (size_t)gy * j.mw + gx;
			const double complex ratio = (1 - ty) * ((1 - tx) * g[0] + tx * g[1]) +
						     ty * ((1 - tx) * g[j.mw] + tx * g[j.mw + 1]);
			const double complex total = dir * (1.0 + ratio);
			const double a = cabs(total);
			if (a < TOF_MIN_AMPLITUDE)
				continue;
			/* the period nearest the true distance (the lower frequencies' job) */
			const vec3 d = pixel_ray(cam, x, y);
			const double r_true = img->depth[i] * sqrt(v3_dot(d, d));
			double r = carg(total) / (2.0 * PI) * wrap;
			r += wrap * floor((r_true - r) / wrap + 0.5);
			/* shot-noise limited: sigma = TOF_NOISE_1M sqrt(albedo / amplitude) */
			uint64_t rng = synth_pixel_rng(seed, 6, i);
			r += TOF_NOISE_1M * sqrt(TOF_ALBEDO / a) * synth_gaussian(&rng);
			out[i] = (float)(r / sqrt(v3_dot(d, d)));
		}
	free(j.mp);
	free(j.direct);
	return 0;
}
