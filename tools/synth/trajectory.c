/* SPDX-License-Identifier: MIT */
/* Camera trajectories of the synthetic sequences (trajectory.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/pose.h>

#include "synth/rng.h"
#include "synth/trajectory.h"

#define DEG (SYNTH_PI / 180.0)

const char *synth_trajectory_names(void)
{
	return "still, pan-RATE (deg/s: pan-15, pan-30, pan-60), sideways, walk, shake, turn, stop, "
	       "start";
}

static void normalize3(double v[3])
{
	double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	for (int k = 0; k < 3; k++)
		v[k] /= l;
}

static void cross3(const double a[3], const double b[3], double out[3])
{
	out[0] = a[1] * b[2] - a[2] * b[1];
	out[1] = a[2] * b[0] - a[0] * b[2];
	out[2] = a[0] * b[1] - a[1] * b[0];
}

/* "Up" in frame 0: the most upward-facing half-space normal (y is down), else -y. */
static void scene_up(const struct synth_scene *s, double up[3])
{
	up[0] = 0.0, up[1] = -1.0, up[2] = 0.0;
	double best = 0.5; /* facing up more than 60 degrees from level */
	for (int i = 0; s && i < s->count; i++) {
		const struct synth_prim *p = &s->prims[i];
		if (p->kind == SYNTH_HALFSPACE && -p->n.y > best) {
			best = -p->n.y;
			up[0] = p->n.x, up[1] = p->n.y, up[2] = p->n.z;
		}
	}
	normalize3(up);
}

/* The level axes: forward (the optical axis without its up part) and right = forward x up. */
static void level_axes(struct synth_trajectory *tr)
{
	const double z[3] = { 0, 0, 1 };
	double d = tr->up[2];
	for (int k = 0; k < 3; k++)
		tr->forward[k] = z[k] - d * tr->up[k];
	normalize3(tr->forward);
	cross3(tr->forward, tr->up, tr->right);
	normalize3(tr->right);
}

/* Six channels of sinusoids, 1/f amplitudes, log-spaced frequencies, scaled to the RMS. */
static void shake_init(struct synth_trajectory *tr, uint64_t seed)
{
	uint64_t rng = seed ^ 0x7368616b65ull;
	const double lf0 = log(SYNTH_SHAKE_F_MIN), lf1 = log(SYNTH_SHAKE_F_MAX);
	for (int c = 0; c < 6; c++) {
		double power = 0.0;
		for (int k = 0; k < SYNTH_SHAKE_TERMS; k++) {
			/* one term in each of K log-spaced bins, inside its middle 80 %: the terms
			 * cover the band and no two beat slowly (the RMS holds over seconds) */
			double u = (k + 0.1 + 0.8 * synth_rng_uniform(&rng)) / SYNTH_SHAKE_TERMS;
			double f = exp(lf0 + (lf1 - lf0) * u);
			double a = 1.0 / f;
			tr->shake[c][k][0] = f;
			tr->shake[c][k][1] = a;
			tr->shake[c][k][2] = 2.0 * SYNTH_PI * synth_rng_uniform(&rng);
			power += 0.5 * a * a;
		}
		/* the RMS of a sum of sinusoids of distinct frequencies: sqrt(sum a^2 / 2) */
		double rms = c < 3 ? SYNTH_SHAKE_RMS_M : SYNTH_SHAKE_RMS_DEG * DEG;
		double scale = rms / sqrt(power);
		tr->shake0[c] = 0.0;
		for (int k = 0; k < SYNTH_SHAKE_TERMS; k++) {
			tr->shake[c][k][1] *= scale;
			tr->shake0[c] += tr->shake[c][k][1] * sin(tr->shake[c][k][2]);
		}
	}
}

static int parse_pan(const char *name, double *rate, struct dao_error *err)
{
	char *end;
	errno = 0;
	double r = strtod(name + 4, &end);
	if (end == name + 4 || *end || errno || !(r >= 1.0 && r <= 720.0))
		return dao_error_set(err, -EINVAL,
				     "trajectory '%s': a pan is pan-RATE with RATE in 1..720 degrees "
				     "per second (e.g. pan-30)", name);
	*rate = r;
	return 0;
}

int synth_trajectory_init(struct synth_trajectory *tr, const char *name,
			  const struct synth_scene *scene, uint64_t seed, struct dao_error *err)
{
	memset(tr, 0, sizeof *tr);
	static const struct {
		const char *name;
		enum synth_trajectory_kind kind;
	} kinds[] = {
		{ "still", SYNTH_TRAJ_STILL }, { "sideways", SYNTH_TRAJ_SIDEWAYS },
		{ "walk", SYNTH_TRAJ_WALK },   { "shake", SYNTH_TRAJ_SHAKE },
		{ "turn", SYNTH_TRAJ_TURN },   { "stop", SYNTH_TRAJ_STOP },
		{ "start", SYNTH_TRAJ_START },
	};
	if (!name || strlen(name) >= sizeof tr->name)
		return dao_error_set(err, -EINVAL, "unknown trajectory: use %s", synth_trajectory_names());
	size_t k;
	for (k = 0; k < sizeof kinds / sizeof kinds[0] && strcmp(kinds[k].name, name) != 0; k++)
		;
	if (k < sizeof kinds / sizeof kinds[0]) {
		tr->kind = kinds[k].kind;
	} else if (strncmp(name, "pan-", 4) == 0) {
		tr->kind = SYNTH_TRAJ_PAN;
		if (parse_pan(name, &tr->rate_deg, err))
			return -EINVAL;
	} else {
		return dao_error_set(err, -EINVAL, "unknown trajectory '%s': use %s", name,
				     synth_trajectory_names());
	}
	snprintf(tr->name, sizeof tr->name, "%s", name);
	scene_up(scene, tr->up);
	level_axes(tr);
	if (tr->kind == SYNTH_TRAJ_SHAKE)
		shake_init(tr, seed);
	synth_trajectory_set_length(tr, 16, 30.0);
	return 0;
}

void synth_trajectory_set_length(struct synth_trajectory *tr, int frames, double fps)
{
	/* frame i is at i / fps, computed the same way: the middle frame's pose is exact */
	tr->change_s = (double)(frames / 2) / fps;
}

void synth_rotation(const double a[3], double angle, double (*R)[3])
{
	const double c = cos(angle), s = sin(angle), C = 1.0 - c;
	R[0][0] = c + a[0] * a[0] * C;
	R[0][1] = a[0] * a[1] * C - a[2] * s;
	R[0][2] = a[0] * a[2] * C + a[1] * s;
	R[1][0] = a[1] * a[0] * C + a[2] * s;
	R[1][1] = c + a[1] * a[1] * C;
	R[1][2] = a[1] * a[2] * C - a[0] * s;
	R[2][0] = a[2] * a[0] * C - a[1] * s;
	R[2][1] = a[2] * a[1] * C + a[0] * s;
	R[2][2] = c + a[2] * a[2] * C;
}

static void identity(struct synth_pose *p)
{
	memset(p, 0, sizeof *p);
	for (int k = 0; k < 3; k++)
		p->R[k][k] = 1.0;
}

static double shake_channel(const struct synth_trajectory *tr, int c, double time)
{
	double v = -tr->shake0[c];
	for (int k = 0; k < SYNTH_SHAKE_TERMS; k++)
		v += tr->shake[c][k][1] * sin(2.0 * SYNTH_PI * tr->shake[c][k][0] * time + tr->shake[c][k][2]);
	return v;
}

/* The rotation by the small-angle vector w (axis w/|w|, angle |w|). */
static void rotation_vector(const double w[3], double (*R)[3])
{
	double a = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
	double axis[3] = { 1, 0, 0 };
	if (a > 0)
		for (int k = 0; k < 3; k++)
			axis[k] = w[k] / a;
	synth_rotation(axis, a, R);
}

/* Turning angle of the robot: constant acceleration from rest, then constant rate. */
static double turn_angle(double time)
{
	const double a = SYNTH_TURN_ACCEL_DEG * DEG, w = SYNTH_TURN_RATE_DEG * DEG, ta = w / a;
	return time < ta ? 0.5 * a * time * time : 0.5 * a * ta * ta + w * (time - ta);
}

void synth_trajectory_pose(const struct synth_trajectory *tr, double time, struct synth_pose *out)
{
	identity(out);
	switch (tr->kind) {
	case SYNTH_TRAJ_STILL:
		break;
	case SYNTH_TRAJ_PAN:
		/* a positive angle about up turns left (y is down): minus, to the right */
		synth_rotation(tr->up, -tr->rate_deg * DEG * time, out->R);
		break;
	case SYNTH_TRAJ_STOP:
		synth_rotation(tr->up, -SYNTH_STOP_RATE_DEG * DEG * fmin(time, tr->change_s), out->R);
		break;
	case SYNTH_TRAJ_START:
		synth_rotation(tr->up, -SYNTH_STOP_RATE_DEG * DEG * fmax(time - tr->change_s, 0.0),
			       out->R);
		break;
	case SYNTH_TRAJ_SIDEWAYS:
		for (int k = 0; k < 3; k++)
			out->t[k] = SYNTH_SIDEWAYS_SPEED * time * tr->right[k];
		break;
	case SYNTH_TRAJ_WALK: {
		/* steps at 2 Hz: 15 mm bob and a 0.3 degree nod; a 10 mm sway at 1 Hz */
		double bob = 0.015 * sin(2.0 * SYNTH_PI * 2.0 * time);
		double sway = 0.010 * sin(2.0 * SYNTH_PI * 1.0 * time);
		for (int k = 0; k < 3; k++)
			out->t[k] = SYNTH_WALK_SPEED * time * tr->forward[k] + bob * tr->up[k] +
				    sway * tr->right[k];
		synth_rotation(tr->right, 0.3 * DEG * sin(2.0 * SYNTH_PI * 2.0 * time), out->R);
		break;
	}
	case SYNTH_TRAJ_SHAKE: {
		double w[3];
		for (int k = 0; k < 3; k++) {
			out->t[k] = shake_channel(tr, k, time);
			w[k] = shake_channel(tr, 3 + k, time);
		}
		rotation_vector(w, out->R);
		break;
	}
	case SYNTH_TRAJ_TURN: {
		/* about the axis through c = -offset * forward: t = c - R c */
		double c[3];
		for (int k = 0; k < 3; k++)
			c[k] = -SYNTH_TURN_OFFSET * tr->forward[k];
		synth_rotation(tr->up, -turn_angle(time), out->R);
		for (int k = 0; k < 3; k++)
			out->t[k] = c[k] - (out->R[k][0] * c[0] + out->R[k][1] * c[1] + out->R[k][2] * c[2]);
		break;
	}
	}
}

void synth_scene_view_from(struct synth_scene *scene, const struct synth_pose *pose)
{
	/* x_c = R^T (x_w - t): the rows of R^T are the columns of R */
	const vec3 rows[3] = {
		v3(pose->R[0][0], pose->R[1][0], pose->R[2][0]),
		v3(pose->R[0][1], pose->R[1][1], pose->R[2][1]),
		v3(pose->R[0][2], pose->R[1][2], pose->R[2][2]),
	};
	const vec3 eye = v3(pose->t[0], pose->t[1], pose->t[2]);
	for (int i = 0; i < scene->count; i++)
		synth_prim_transform(&scene->prims[i], rows, eye);
}

void synth_quat_from_matrix(const double R[3][3], double q[4])
{
	double r[9];
	memcpy(r, R, sizeof r);
	dao_pose_matrix_to_quat(r, q);
}

void synth_matrix_from_quat(const double qin[4], double R[3][3])
{
	const double n = sqrt(qin[0] * qin[0] + qin[1] * qin[1] + qin[2] * qin[2] + qin[3] * qin[3]);
	const double q[4] = { qin[0] / n, qin[1] / n, qin[2] / n, qin[3] / n };
	double r[9];
	dao_pose_quat_to_matrix(q, r);
	memcpy(R, r, sizeof r);
}

double synth_rotation_angle(const double Ra[3][3], const double Rb[3][3])
{
	/* |Ra - Rb|_F = 2 sqrt(2) sin(angle / 2): unlike acos of the trace, exact near 0 */
	double f = 0.0;
	for (int i = 0; i < 3; i++)
		for (int k = 0; k < 3; k++)
			f += (Ra[i][k] - Rb[i][k]) * (Ra[i][k] - Rb[i][k]);
	double s = sqrt(f) / (2.0 * sqrt(2.0));
	return 2.0 * asin(s > 1.0 ? 1.0 : s);
}

int synth_pose_write(FILE *f, double time, const struct synth_pose *pose)
{
	double q[4];
	synth_quat_from_matrix(pose->R, q);
	int r = fprintf(f, "%.6f %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n", time, pose->t[0],
			pose->t[1], pose->t[2], q[0], q[1], q[2], q[3]);
	return r < 0 ? -EIO : 0;
}

void synth_pose_list_free(struct synth_pose_list *l)
{
	free(l->time);
	free(l->pose);
	memset(l, 0, sizeof *l);
}
