/* SPDX-License-Identifier: MIT */
#ifndef DAO_TF_IMU_TRACK_H
#define DAO_TF_IMU_TRACK_H

/*
 * An IMU's rotation over time from its messages (sensor_msgs/Imu): its
 * orientation where it reports one, else its angular velocity integrated
 * from the first message on.  What the camera poses take of an IMU
 * (plugin/source_poses.c): a rotation only, no translation.
 */
#include <stddef.h>
#include <stdint.h>

struct dao_imu_sample {
	uint64_t stamp_ns;
	double q[4]; /* in: the orientation (orientation mode); out: the rotation, x y z w */
	double w[3]; /* angular velocity, rad/s, in the IMU's frame */
	size_t order; /* set by dao_imu_track: the arrival order, which breaks ties */
	size_t segment; /* out: how many gaps precede the sample */
};

/*
 * Sorts the n samples by stamp (a recorder writes them in arrival order),
 * keeps the first of samples with the same stamp (a driver's repeat; the tf
 * buffer keeps the last of a transform's, a correction), and gives each kept one
 * its rotation q, from the IMU's frame to a fixed one: with `orientation`
 * the one it reports (normalised); else the angular velocity integrated
 * from the identity at the first sample.  Between two samples the rate is
 * taken as their mean and constant in the IMU's frame, so the rotation
 * grows by exp(w dt / 2) multiplied on the right (a body rate: q' = q (0, w)
 * / 2; Solà, "Quaternion kinematics for the error-state Kalman filter",
 * 2017, the integration of rotation rates); exact for a constant rate,
 * within 2.1e-5 rad of a 1000 times finer integration between two frames
 * of a hand's shake (tests/io/test_imu_track.c), where a motion seed needs
 * a tenth of a degree.  Two samples more than gap_ns apart are not
 * integrated across (the turn between them is unknown): the later one
 * keeps the earlier one's rotation and starts a new segment.  Returns the
 * samples kept (the first ones of s).
 */
size_t dao_imu_track(struct dao_imu_sample *s, size_t n, int orientation, uint64_t gap_ns);

#endif
