/* SPDX-License-Identifier: MIT */
/*
 * Projective point-to-plane ICP (motion/icp.h).  Scalar; the source points
 * are gathered once per frame into structure-of-arrays scratch (x, y, z and
 * the normal, compacted), so the per-step loop reads them in order and is
 * ready for SIMD lanes; the target side is a gather from the previous plane.
 */
#include <math.h>
#include <string.h>

#include "motion/icp.h"
#include "motion/icp_pairs.h"
#include "motion/icp_source.h"
#include "motion/reproject.h"
#include "core/threadpool.h"

enum { SOA = 6 }; /* x, y, z, nx, ny, nz */

void dao_pose_identity(struct dao_pose *p)
{
	memset(p, 0, sizeof *p);
	p->r[0] = p->r[4] = p->r[8] = 1.0;
}

double dao_pose_angle(const struct dao_pose *p)
{
	const double c = 0.5 * (p->r[0] + p->r[4] + p->r[8] - 1.0);
	const double s = 0.5 * sqrt((p->r[7] - p->r[5]) * (p->r[7] - p->r[5]) +
				    (p->r[2] - p->r[6]) * (p->r[2] - p->r[6]) +
				    (p->r[3] - p->r[1]) * (p->r[3] - p->r[1]));
	return atan2(s, c);
}

double dao_pose_distance(const struct dao_pose *p)
{
	return sqrt(p->t[0] * p->t[0] + p->t[1] * p->t[1] + p->t[2] * p->t[2]);
}

void dao_icp_setup_default(struct dao_icp_setup *s)
{
	*s = (struct dao_icp_setup){
		.step = 4,
		.coarse_iterations = 4,
		.iterations = 3,
		/* from the last frame's motion 2 + 2 steps were as good as
		 * 4 + 3 (docs/perf/icp3.md); from the identity (the first
		 * frame, after a refusal) they were not */
		.seeded_coarse_iterations = 2,
		.seeded_iterations = 2,
		/* 2.3 mm at most on the tune set's ToF frames, 6.8-30 mm after a
		 * stop or a start (docs/perf/icp-seeded.md) */
		.seeded_far = 0.005f,
		.normal_radius = 6,
		.dist_gate = 0.10f,
		.cos_gate = 0.8660254f, /* 30 degrees */
		.tukey = 4.685f,
		.noise_k = 0.0028f,
		.quantum = 0.001f,
		.max_angle = 0.2618f, /* 15 degrees a frame */
		.max_dist = 0.25f,
		.min_inlier_share = 0.3f,
		.min_inliers = 200,
		.min_cond = 1e-2f,
		.max_rms = 0.03f,
		.edge = 0.03f,
		.prior_angle = 0.00524f, /* 0.3 degrees */
		.prior_dist = 0.003f,
		/* every step on the pool: on an idle 2-core host the estimate's
		 * wall time falls by about 30 % (the motion's by a quarter), the
		 * CPU time unchanged within its spread; on a host with more
		 * runnable threads than cores it costs 22 % more CPU (the
		 * worker's spin between steps) for the same wall time
		 * (docs/perf/icp5.md; motion2.md measured the latter alone) */
		.pool_min_points = 0,
	};
}

/* grid columns and rows, and the floats from one plane of a grid row's
 * output (motion/icp_source.h) to the next */
static int grid_w(const struct dao_icp_setup *s, int w) { return (w + s->step - 1) / s->step; }
static int grid_h(const struct dao_icp_setup *s, int h) { return (h + s->step - 1) / s->step; }
static size_t grid_stride(const struct dao_icp_setup *s, int w)
{
	return ((size_t)grid_w(s, w) + DAO_ICP_PAD - 1) / DAO_ICP_PAD * DAO_ICP_PAD;
}

static size_t grid_cap(const struct dao_icp_setup *s, int w, int h)
{
	const size_t n = (size_t)grid_w(s, w) * (size_t)grid_h(s, h);
	return (n + DAO_ICP_PAD - 1) / DAO_ICP_PAD * DAO_ICP_PAD;
}

static size_t sums_floats(size_t cap)
{
	return (cap + DAO_ICP_CHUNK - 1) / DAO_ICP_CHUNK * (sizeof(struct dao_icp_sums) + 7) / 8 * 2;
}

size_t dao_icp_scratch_floats(const struct dao_icp_setup *s, int w, int h)
{
	const size_t cap = grid_cap(s, w, h), npix = (size_t)w * (size_t)h;
	/* the source arrays, the target's depth, the grid's rows */
	const size_t work = SOA * cap + npix + 6 * (size_t)grid_h(s, h) * grid_stride(s, w);
	/* ... or the history's reprojection, which shares it */
	const size_t rp = dao_history_reproject_scratch(w, h);
	return sums_floats(cap) + (work > rp ? work : rp);
}

/* the frame's inputs in one dispatch: items [0, gh) are the source grid's
 * rows, the others bands of TARGET_ROWS rows of the target's depth */
enum { TARGET_ROWS = 16 };
struct prep_job {
	const struct dao_icp_grid *grid;
	dao_icp_source_fn source;
	dao_icp_target_fn target;
	float *rows; /* grid row j at rows + 6 j stride */
	int gh;
	const float *inv;
	const uint8_t *count;
	float *tz;
	int w, h;
};

static void prep_items(void *arg, int i0, int i1)
{
	const struct prep_job *j = arg;
	for (int i = i0; i < i1; i++) {
		if (i < j->gh) {
			j->source(j->grid, i * j->grid->step, j->rows + (size_t)i * 6 * j->grid->stride);
			continue;
		}
		const int y0 = (i - j->gh) * TARGET_ROWS;
		const int y1 = y0 + TARGET_ROWS < j->h ? y0 + TARGET_ROWS : j->h;
		j->target(j->inv, j->count, j->tz, (size_t)y0 * (size_t)j->w, (size_t)y1 * (size_t)j->w);
	}
}

/*
 * The source grid's rows (rows: each six planes `stride` apart, z > 0
 * marking a point) into scratch (SoA, compacted, zero-padded to a multiple
 * of DAO_ICP_PAD): first the coarse grid's points (every second row and
 * column of the grid), then the others; *coarse gets the first part's count.
 */
static int gather_source(const float *rows, int gw, int gh, size_t stride, float *src, size_t cap,
			 int *coarse, float *near_z, float *mean_z)
{
	int k = 0;
	double sum = 0.0;
	float near = INFINITY;
	for (int pass = 0; pass < 2; pass++) {
		for (int gy = 0; gy < gh; gy++) {
			const float *row = rows + (size_t)gy * 6 * stride;
			/* the coarse grid: even rows, even columns; then the rest */
			const int c_row = gy % 2 == 0;
			if (pass == 0 && !c_row)
				continue;
			const int x0 = pass == 0 || !c_row ? 0 : 1, dx = pass == 0 || c_row ? 2 : 1;
			for (int gx = x0; gx < gw; gx += dx) {
				const float z = row[2 * stride + (size_t)gx];
				if (!(z > 0.0f))
					continue;
				for (int j = 0; j < SOA; j++)
					src[(size_t)j * cap + (size_t)k] = row[(size_t)j * stride + (size_t)gx];
				sum += z;
				near = z < near ? z : near; /* z > 0 and finite: fminf */
				k++;
			}
		}
		if (pass == 0)
			*coarse = k;
	}
	for (size_t j = 0; j < SOA; j++)
		for (size_t i = (size_t)k; i < ((size_t)k + DAO_ICP_PAD - 1) / DAO_ICP_PAD * DAO_ICP_PAD; i++)
			src[j * cap + i] = 0.0f;
	*near_z = k ? near : 0.0f;
	*mean_z = k ? (float)(sum / k) : 1.0f;
	return k;
}

/* one step's chunks on the pool: chunk c into sums[c] */
struct pairs_job {
	const struct dao_icp_step *st;
	dao_icp_pairs_fn fn;
	struct dao_icp_sums *sums;
	int count;
};

static void pairs_chunks(void *arg, int c0, int c1)
{
	const struct pairs_job *j = arg;
	for (int c = c0; c < c1; c++) {
		const int i1 = (c + 1) * DAO_ICP_CHUNK < j->count ? (c + 1) * DAO_ICP_CHUNK : j->count;
		j->fn(j->st, c * DAO_ICP_CHUNK, i1, &j->sums[c]);
	}
}

static void run_rows(struct dao_pool *pool, int rows, int min_rows, dao_pool_fn fn, void *arg)
{
	if (pool)
		dao_pool_run(pool, rows, min_rows, fn, arg);
	else
		fn(arg, 0, rows);
}

/* The normal equations of one step: A (6x6, rotation columns scaled by 1/scale) and b. */
struct normal_eq {
	double a[36], b[6], r2, e2w, wsum;
	int n;
};

/* the step's pairs over the first `count` source points, chunk by chunk, the
 * chunks' sums added in their order whatever the threads */
static void accumulate(const struct dao_icp_setup *s, struct dao_icp_step *st,
		       struct dao_icp_sums *sums, int count, struct normal_eq *eq)
{
	const int chunks = (count + DAO_ICP_CHUNK - 1) / DAO_ICP_CHUNK;
	struct pairs_job job = {.st = st, .fn = s->pairs ? s->pairs : dao_icp_pairs_ref,
				.sums = sums, .count = count};
	/* a step of few points on the calling thread (waking the pool's
	 * workers costs more than they would save); else one band per thread */
	struct dao_pool *pool = count >= s->pool_min_points ? s->pool : NULL;
	const int threads = pool ? dao_pool_threads(pool) : 1;
	run_rows(pool, chunks, (chunks + threads - 1) / threads, pairs_chunks, &job);
	memset(eq, 0, sizeof *eq);
	for (int c = 0; c < chunks; c++) {
		int k = 0;
		for (int a = 0; a < 6; a++) {
			for (int b = a; b < 6; b++)
				eq->a[a * 6 + b] += sums[c].a[k++];
			eq->b[a] += sums[c].b[a];
		}
		eq->r2 += sums[c].r2;
		eq->e2w += sums[c].e2w;
		eq->wsum += sums[c].wsum;
		eq->n += sums[c].n;
	}
	for (int a = 0; a < 6; a++)
		for (int b = 0; b < a; b++)
			eq->a[a * 6 + b] = eq->a[b * 6 + a];
}

/* Solves A x = b by Cholesky (A symmetric positive definite); -1 if it is not. */
static int cholesky_solve(const double a_in[36], const double b[6], double x[6])
{
	double l[36] = {0};
	for (int i = 0; i < 6; i++)
		for (int j = 0; j <= i; j++) {
			double s = a_in[i * 6 + j];
			for (int k = 0; k < j; k++)
				s -= l[i * 6 + k] * l[j * 6 + k];
			if (i == j) {
				if (!(s > 0.0))
					return -1;
				l[i * 6 + i] = sqrt(s);
			} else {
				l[i * 6 + j] = s / l[j * 6 + j];
			}
		}
	double y[6];
	for (int i = 0; i < 6; i++) {
		double s = b[i];
		for (int k = 0; k < i; k++)
			s -= l[i * 6 + k] * y[k];
		y[i] = s / l[i * 6 + i];
	}
	for (int i = 5; i >= 0; i--) {
		double s = y[i];
		for (int k = i + 1; k < 6; k++)
			s -= l[k * 6 + i] * x[k];
		x[i] = s / l[i * 6 + i];
	}
	return 0;
}

/* Smallest / largest eigenvalue of a symmetric 6x6 matrix (cyclic Jacobi). */
static double condition(const double a_in[36])
{
	double a[36];
	memcpy(a, a_in, sizeof a);
	for (int sweep = 0; sweep < 30; sweep++) {
		double off = 0.0;
		for (int p = 0; p < 6; p++)
			for (int q = p + 1; q < 6; q++)
				off += a[p * 6 + q] * a[p * 6 + q];
		if (off < 1e-30)
			break;
		for (int p = 0; p < 6; p++)
			for (int q = p + 1; q < 6; q++) {
				const double apq = a[p * 6 + q];
				if (fabs(apq) < 1e-300)
					continue;
				const double th = (a[q * 6 + q] - a[p * 6 + p]) / (2.0 * apq);
				const double t = (th >= 0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
				const double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
				for (int k = 0; k < 6; k++) { /* columns p, q */
					const double kp = a[k * 6 + p], kq = a[k * 6 + q];
					a[k * 6 + p] = c * kp - s * kq;
					a[k * 6 + q] = s * kp + c * kq;
				}
				for (int k = 0; k < 6; k++) { /* rows p, q */
					const double pk = a[p * 6 + k], qk = a[q * 6 + k];
					a[p * 6 + k] = c * pk - s * qk;
					a[q * 6 + k] = s * pk + c * qk;
				}
			}
	}
	double lo = INFINITY, hi = 0.0;
	for (int i = 0; i < 6; i++) {
		lo = fmin(lo, a[i * 7]);
		hi = fmax(hi, a[i * 7]);
	}
	return hi > 0.0 ? fmax(lo, 0.0) / hi : 0.0;
}

/* T <- exp(xi) T, xi = (omega, v); the rotation by Rodrigues' formula. */
static void pose_update(struct dao_pose *T, const double w[3], const double v[3])
{
	const double th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
	double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
	if (th > 0.0) {
		const double k[3] = {w[0] / th, w[1] / th, w[2] / th};
		const double c = cos(th), s = sin(th), cc = 1.0 - c;
		const double K[9] = {0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0};
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				R[i * 3 + j] = (i == j ? c : 0.0) + s * K[i * 3 + j] + cc * k[i] * k[j];
	}
	struct dao_pose n;
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			n.r[i * 3 + j] = R[i * 3] * T->r[j] + R[i * 3 + 1] * T->r[3 + j] +
					 R[i * 3 + 2] * T->r[6 + j];
		n.t[i] = R[i * 3] * T->t[0] + R[i * 3 + 1] * T->t[1] + R[i * 3 + 2] * T->t[2] +
			 v[i];
	}
	*T = n;
}

static enum dao_icp_verdict verdict(const struct dao_icp_setup *s, const struct dao_icp_result *o)
{
	if (o->inliers < s->min_inliers || (float)o->inliers < s->min_inlier_share * (float)o->points)
		return DAO_ICP_FEW_POINTS;
	if (!(o->cond >= s->min_cond))
		return DAO_ICP_DEGENERATE;
	if (!(o->rms <= s->max_rms))
		return DAO_ICP_RESIDUAL;
	if (!(dao_pose_angle(&o->pose) <= s->max_angle) ||
	    !(dao_pose_distance(&o->pose) <= s->max_dist))
		return DAO_ICP_MOTION;
	return DAO_ICP_OK;
}

static void step_setup(const struct dao_icp_setup *s, const struct dao_camera *cam,
		       const float *tz, const float *src, size_t cap, double scale,
		       struct dao_icp_step *st)
{
	*st = (struct dao_icp_step){
		.tz = tz, .w = (int)cam->width, .h = (int)cam->height, .r = s->normal_radius,
		.ax = cam->ax, .bx = cam->bx, .ay = cam->ay, .by = cam->by,
		.inv_ax = 1.0f / cam->ax, .inv_ay = 1.0f / cam->ay, .src = src, .cap = cap,
		.inv_scale = (float)(1.0 / scale), .cos_gate = s->cos_gate,
		.k2 = s->noise_k * s->noise_k, .q2 = s->quantum * s->quantum / 12.0f,
		.edge = s->edge,
	};
	st->noise_weight = 1;
	/* float depth without a noise figure (clean, rendered depth): 1 mm,
	 * the order of the residual a pixel's sampling leaves on a slanted
	 * surface at a few metres (0.1 mm kept only the surfaces facing the
	 * camera, and a room became a flat wall: test ao-history's pan) */
	if (!(st->q2 >= 1e-8f))
		st->q2 = 1e-6f;
}

/*
 * The motion prior: d = log(T P^-1) (small angles), in the step's units
 * (rotation times `scale`), so that the prior term adds lambda (x + d)^2.
 */
static void prior_deviation(const struct dao_pose *T, const struct dao_pose *P, double scale,
			    double d[6])
{
	double Rd[9];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			Rd[i * 3 + j] = T->r[i * 3] * P->r[j * 3] + T->r[i * 3 + 1] * P->r[j * 3 + 1] +
					T->r[i * 3 + 2] * P->r[j * 3 + 2];
	d[0] = 0.5 * (Rd[7] - Rd[5]) * scale;
	d[1] = 0.5 * (Rd[2] - Rd[6]) * scale;
	d[2] = 0.5 * (Rd[3] - Rd[1]) * scale;
	for (int i = 0; i < 3; i++)
		d[3 + i] = T->t[i] - (Rd[i * 3] * P->t[0] + Rd[i * 3 + 1] * P->t[1] +
				      Rd[i * 3 + 2] * P->t[2]);
}

/* Gauss-Newton steps on the first `count` points; 1 to go on, 0 done, -1 refused. */
static int level(const struct dao_icp_setup *s, struct dao_icp_step *st, struct dao_icp_sums *sums,
		 int count, int steps, int first, double scale, double tol, double *sigma,
		 const struct dao_pose *prior, struct normal_eq *eq, struct dao_icp_result *out)
{
	for (int it = 0; it < steps; it++) {
		/* the distance gate from 4 times its value down to it, and the
		 * residuals' scale from 10 sigma down to what the last step
		 * measured (at least the noise model's): a first step from a
		 * far start pairs the surfaces that constrain it */
		const int k = first + it;
		const float gate = s->dist_gate * (float)(k < 2 ? 4 >> k : 1);
		st->gate2 = gate * gate;
		st->tukey_c = s->tukey * (float)*sigma;
		for (int i = 0; i < 9; i++)
			st->R[i] = (float)out->pose.r[i];
		for (int i = 0; i < 3; i++)
			st->t[i] = (float)out->pose.t[i];
		accumulate(s, st, sums, count, eq);
		out->iterations++;
		out->inliers = eq->n;
		if (eq->n < s->min_inliers)
			return 0;
		/* the biweight's mean square of e is 0.828 of a normal's variance */
		*sigma = eq->wsum > 0.0 ? sqrt(eq->e2w / (0.828 * eq->wsum)) : 10.0;
		*sigma = fmin(fmax(*sigma, 1.0), 10.0);
		/* a flat wall leaves in-plane motion free: stop rather than take a
		 * wild step (the first steps, from a poor start, may be worse
		 * conditioned than the last: the verdict takes the last's) */
		out->cond = (float)condition(eq->a);
		/* the prior (the last frame's motion: the camera keeps its
		 * speed but for a hand's or a robot's acceleration) after the
		 * condition, which is the data's alone */
		double a[36], b[6], x[6];
		memcpy(a, eq->a, sizeof a);
		memcpy(b, eq->b, sizeof b);
		if (prior && s->prior_angle > 0.0f && s->prior_dist > 0.0f) {
			double d[6];
			prior_deviation(&out->pose, prior, scale, d);
			for (int i = 0; i < 6; i++) {
				const double sd = i < 3 ? s->prior_angle * scale : s->prior_dist;
				a[i * 7] += 1.0 / (sd * sd);
				b[i] -= d[i] / (sd * sd);
			}
		}
		if (!(out->cond >= 1e-3f * s->min_cond) || cholesky_solve(a, b, x)) {
			out->reason = DAO_ICP_DEGENERATE;
			return -1;
		}
		const double w[3] = {x[0] / scale, x[1] / scale, x[2] / scale};
		pose_update(&out->pose, w, x + 3);
		if (!isfinite(out->pose.t[0] + out->pose.t[1] + out->pose.t[2] + out->pose.r[0])) {
			out->reason = DAO_ICP_NOT_FINITE;
			return -1;
		}
		/* converged: the step moves no point at the mean depth by more than tol */
		double big = 0.0;
		for (int i = 0; i < 6; i++)
			big = fmax(big, fabs(x[i]));
		out->step = (float)big;
		if (big < tol)
			break;
	}
	return 1;
}

void dao_icp_estimate(const struct dao_icp_setup *s, const struct dao_camera *cam,
		      const float *prev_inv, const uint8_t *prev_count, const float *cur_z,
		      const struct dao_pose *prior, float *scratch, struct dao_icp_result *out)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t cap = grid_cap(s, w, h);
	struct dao_icp_sums *sums = (struct dao_icp_sums *)(void *)scratch;
	float *src = scratch + sums_floats(cap), *tz = src + SOA * cap;
	float mean_z;
	int coarse = 0;
	memset(out, 0, sizeof *out);
	if (prior)
		out->pose = *prior;
	else
		dao_pose_identity(&out->pose);
	/* the source grid's rows and the target's depth in one dispatch */
	const int gw = grid_w(s, w), gh = grid_h(s, h);
	const size_t stride = grid_stride(s, w);
	float *rows = tz + (size_t)w * (size_t)h;
	const struct dao_icp_grid grid = {
		.z = cur_z, .w = w, .h = h, .r = s->normal_radius, .step = s->step, .gw = gw,
		.stride = stride, .edge_r = s->edge * (float)s->normal_radius,
		.ax = cam->ax, .bx = cam->bx, .ay = cam->ay, .by = cam->by,
		.rax = (float)s->normal_radius * cam->ax, .ray = (float)s->normal_radius * cam->ay,
	};
	struct prep_job pj = {
		.grid = &grid, .source = s->source ? s->source : dao_icp_source_ref,
		.target = s->target ? s->target : dao_icp_target_ref, .rows = rows, .gh = gh,
		.inv = prev_inv, .count = prev_count, .tz = tz, .w = w, .h = h,
	};
	run_rows(s->pool, gh + (h + TARGET_ROWS - 1) / TARGET_ROWS, 1, prep_items, &pj);
	out->points = gather_source(rows, gw, gh, stride, src, cap, &coarse, &out->near_z, &mean_z);
	out->reason = DAO_ICP_FEW_POINTS;
	if (out->points < s->min_inliers)
		return;
	/* rotation in units of the motion it gives at the mean depth, so that
	 * the system's eigenvalues compare */
	const double scale = mean_z;
	struct dao_icp_step st;
	step_setup(s, cam, tz, src, cap, scale, &st);
	struct normal_eq eq = {0};
	double sigma = 10.0;
	/* coarse to fine: the coarse grid's points first, where there are
	 * enough of them, then all (steps below 0.1 mm, then 0.01 mm, end a level) */
	const int n0 = coarse >= 4 * s->min_inliers ? coarse : out->points;
	int n_coarse = prior ? s->seeded_coarse_iterations : s->coarse_iterations;
	int n_fine = prior ? s->seeded_iterations : s->iterations;
	int go = level(s, &st, sums, n0, n_coarse, 0, scale, 1e-4, &sigma, prior, &eq, out);
	/* a seeded start still far after its coarse steps: the motion changed
	 * (a stop, a start), the prior was wrong; the unseeded counts' rest */
	if (go > 0 && prior && out->step > s->seeded_far && n_coarse < s->coarse_iterations) {
		go = level(s, &st, sums, n0, s->coarse_iterations - n_coarse, n_coarse, scale, 1e-4,
			   &sigma, prior, &eq, out);
		n_coarse = s->coarse_iterations, n_fine = s->iterations;
	}
	if (go > 0)
		go = level(s, &st, sums, out->points, n_fine, n_coarse, scale, 1e-5, &sigma, prior,
			   &eq, out);
	if (go < 0)
		return;
	out->inliers = eq.n;
	out->rms = eq.n ? (float)sqrt(eq.r2 / eq.n) : INFINITY;
	/* the verdict's condition is the geometry's: the last step's pairs
	 * unweighted by the noise (which leans on the near and the grazing
	 * surfaces and would hide a flat wall's free directions), over the
	 * coarse grid's points only: a ratio of eigenvalues, which a quarter
	 * of the points spread over the same image measures as well, for a
	 * quarter of a fine step (docs/perf/icp3.md) */
	st.noise_weight = 0;
	accumulate(s, &st, sums, n0, &eq);
	out->cond = eq.n ? (float)condition(eq.a) : 0.0f;
	out->reason = verdict(s, out);
	out->valid = out->reason == DAO_ICP_OK;
}

double dao_pose_pixel_extent(const struct dao_pose *p, const struct dao_camera *cam, double z)
{
	const double us[5] = {0, cam->width - 1.0, 0, cam->width - 1.0, cam->cx};
	const double vs[5] = {0, 0, cam->height - 1.0, cam->height - 1.0, cam->cy};
	double worst = 0.0;
	for (int k = 0; k < 5; k++) {
		double c[3], q[3], u, v;
		dao_camera_pixel_to_view(cam, us[k], vs[k], z, c);
		for (int i = 0; i < 3; i++)
			q[i] = p->r[i * 3] * c[0] + p->r[i * 3 + 1] * c[1] + p->r[i * 3 + 2] * c[2] +
			       p->t[i];
		if (dao_camera_view_to_pixel(cam, q, &u, &v))
			return INFINITY;
		worst = fmax(worst, hypot(u - us[k], v - vs[k]));
	}
	return worst;
}
