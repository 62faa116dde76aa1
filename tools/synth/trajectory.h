/* SPDX-License-Identifier: MIT */
/*
 * Camera trajectories of the synthetic sequences (issue #37): a still
 * camera, pans, a sideways move, a walk, a hand's shake, a robot turning
 * in place and a pan that stops or starts dead, as the camera's pose per frame.  Internal to the tools and tests.
 *
 * Poses are camera to world, x_w = R x_c + t, in metres.  The world frame is
 * the optical frame of the camera at frame 0 (x right, y down, z forward), so
 * the pose of frame 0 is the identity and a scene built for that camera
 * (scenes.c) needs no other transform.  Turns are about the scene's "up"
 * (the normal of its floor in that frame), so a pan of a camera that looks
 * down at the floor stays level.
 *
 * Files: TUM RGB-D's trajectory format, one pose a line,
 *   timestamp tx ty tz qx qy qz qw
 * (seconds; position of the optical centre; unit quaternion of R, Hamilton
 * convention, w last), '#' starts a comment line.
 */
#ifndef DAO_SYNTH_TRAJECTORY_H
#define DAO_SYNTH_TRAJECTORY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <depthao/error.h>

#include "synth/synth.h"

struct synth_pose {
	double R[3][3];   /* rotation, camera to world */
	double t[3];      /* the optical centre in the world, m */
};

enum synth_trajectory_kind {
	SYNTH_TRAJ_STILL,
	SYNTH_TRAJ_PAN,       /* about up through the optical centre, constant rate, to the right */
	SYNTH_TRAJ_SIDEWAYS,  /* to the right, level, 0.5 m/s */
	SYNTH_TRAJ_WALK,      /* forward, level, 1 m/s, with a step's bob, sway and nod */
	SYNTH_TRAJ_SHAKE,     /* a hand holding the camera still: smooth, seeded, 0.5-5 Hz */
	SYNTH_TRAJ_TURN,      /* a robot turning right in place: the camera 15 cm before the axis */
	SYNTH_TRAJ_STOP,      /* a pan at 60 deg/s that stops dead at the sequence's middle frame */
	SYNTH_TRAJ_START,     /* still, then a pan at 60 deg/s from the middle frame on, at once */
};

#define SYNTH_PI 3.14159265358979323846

#define SYNTH_SHAKE_TERMS 6              /* sinusoids per degree of freedom */
#define SYNTH_SHAKE_F_MIN 0.5            /* Hz */
#define SYNTH_SHAKE_F_MAX 5.0            /* Hz */
#define SYNTH_SHAKE_RMS_M 0.002          /* per axis, m */
#define SYNTH_SHAKE_RMS_DEG 0.25         /* per axis, degrees */
#define SYNTH_SIDEWAYS_SPEED 0.5         /* m/s */
#define SYNTH_WALK_SPEED 1.0             /* m/s */
#define SYNTH_TURN_RATE_DEG 60.0         /* deg/s, reached after ... */
#define SYNTH_TURN_ACCEL_DEG 240.0       /* deg/s^2 from rest */
#define SYNTH_TURN_OFFSET 0.15           /* m, the camera before the turning axis */
#define SYNTH_STOP_RATE_DEG 60.0         /* deg/s, stop and start's pan */

struct synth_trajectory {
	enum synth_trajectory_kind kind;
	char name[32];
	double rate_deg;                   /* pan: deg/s */
	double up[3], right[3], forward[3];/* level axes in the world frame */
	/* shake: per degree of freedom (tx, ty, tz, rx, ry, rz) and term: f (Hz), amplitude, phase */
	double shake[6][SYNTH_SHAKE_TERMS][3];
	double shake0[6];                  /* the sum at time 0, subtracted: pose 0 is the identity */
	double change_s;                   /* stop, start: when the pan stops or starts, s */
};

/* The names, for the help text: "still, pan-RATE, sideways, walk, shake, turn, stop, start". */
const char *synth_trajectory_names(void);

/*
 * A trajectory by name (still, pan-RATE with RATE in degrees per second, 1..720,
 * sideways, walk, shake, turn, stop, start) for a scene whose frame-0 camera sees
 * `scene` (its floor gives "up"; a scene without one gets -y).  `seed` draws the
 * shake.  Stop and start change at the middle of 16 frames at 30 fps (frame 8)
 * until synth_trajectory_set_length() says otherwise.  0, or -EINVAL with a message.
 */
int synth_trajectory_init(struct synth_trajectory *tr, const char *name,
			  const struct synth_scene *scene, uint64_t seed, struct dao_error *err);

/*
 * The sequence's length: stop's pan stops dead, start's starts at once, at its
 * middle frame, frames / 2 (rounded down), at (frames / 2) / fps seconds: the
 * frame pairs before it move by the whole 60 deg/s / fps, those after it by
 * nothing (stop; start the other way round), with no pair in between.
 */
void synth_trajectory_set_length(struct synth_trajectory *tr, int frames, double fps);

/* The pose at `time` seconds (time 0: the identity). */
void synth_trajectory_pose(const struct synth_trajectory *tr, double time, struct synth_pose *out);

/* Moves a scene built for the world (frame 0's camera) into the optical frame of a camera at `pose`. */
void synth_scene_view_from(struct synth_scene *scene, const struct synth_pose *pose);

/* Rotation by `angle` radians about the unit axis a (Rodrigues). */
void synth_rotation(const double a[3], double angle, double (*R)[3]);

/* Unit quaternion (x, y, z, w; w >= 0) of a rotation matrix, and back (q need not be unit):
 * <depthao/pose.h>'s conversions for the [3][3] layout. */
void synth_quat_from_matrix(const double R[3][3], double q[4]);
void synth_matrix_from_quat(const double q[4], double R[3][3]);

/* Angle of the rotation R_a^T R_b, radians. */
double synth_rotation_angle(const double Ra[3][3], const double Rb[3][3]);

/* One TUM line "timestamp tx ty tz qx qy qz qw\n"; 0 or -errno. */
int synth_pose_write(FILE *f, double time, const struct synth_pose *pose);

struct synth_pose_list {
	size_t count;
	double *time;
	struct synth_pose *pose;
};

#define SYNTH_POSES_MAX 1000000

/*
 * Reads a TUM trajectory from text (`len` bytes, need not be NUL-terminated):
 * 8 finite numbers a line, quaternions of norm 1 within 1e-3 (normalised),
 * timestamps increasing, at most SYNTH_POSES_MAX lines.  `what` names the
 * source in messages.  0, or -EINVAL / -ENOMEM with a message naming the line.
 */
int synth_poses_parse(const char *text, size_t len, const char *what, struct synth_pose_list *out,
		      struct dao_error *err);

/* synth_poses_parse() of a file (at most 64 MB). */
int synth_poses_read(const char *path, struct synth_pose_list *out, struct dao_error *err);

void synth_pose_list_free(struct synth_pose_list *l);

#endif
