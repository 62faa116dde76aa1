/* SPDX-License-Identifier: MIT */
#ifndef DAO_TF_RIGID_H
#define DAO_TF_RIGID_H

/*
 * Rigid transforms as tf carries them: a unit quaternion q = (x, y, z, w)
 * (w last) and a translation t, mapping a point of the child frame into the
 * parent frame: p_parent = R(q) p_child + t.
 */

struct dao_rigid {
	double q[4]; /* x, y, z, w */
	double t[3]; /* metres */
};

/* The identity. */
void dao_rigid_identity(struct dao_rigid *a);
/* a then b as one transform: out = a * b (b's child -> a's parent); out may alias a or b. */
void dao_rigid_compose(const struct dao_rigid *a, const struct dao_rigid *b, struct dao_rigid *out);
/* The inverse (parent -> child); out may alias a. */
void dao_rigid_inverse(const struct dao_rigid *a, struct dao_rigid *out);
/*
 * The transform s of the way from a (s = 0) to b (s = 1): the translation
 * linear, the rotation spherical (slerp) along the shorter arc
 * (dao_pose_interpolate()); out may alias a or b.
 */
void dao_rigid_interpolate(const struct dao_rigid *a, const struct dao_rigid *b, double s,
			   struct dao_rigid *out);
/*
 * Checks a transform from a message: 0 (its quaternion normalised when its
 * norm is within `tolerance` of 1), -EINVAL when a value is not finite, the
 * norm is farther from 1, or the translation is beyond 1e6 m (why: a phrase).
 */
int dao_rigid_check(struct dao_rigid *a, double tolerance, const char **why);

#endif
