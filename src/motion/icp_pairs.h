/* SPDX-License-Identifier: MIT */
/*
 * One Gauss-Newton step's pairs of the motion estimate (motion/icp.h): the
 * kernel that pairs a range of source points with the target and sums their
 * weighted normal equations.  The reference (icp_pairs.c, doubles) is the
 * oracle; the kernel sets (icp_pairs_simd.inc.c) sum each lane in floats
 * and add the lanes in doubles at the end of the range, within a bound of
 * the reference that tests/simd/test_icp_pairs.c states.
 *
 * Per pair: the source point s (current frame) moved by the pose, p = R s + t,
 * projected to the target pixel (nearest), q and its normal m there (central
 * differences over `r` pixels, refused at a depth edge), d = p - q, the
 * point-to-plane residual res = m . d.  Refused: no target data or normal,
 * |d| beyond the gate, normals differing by more than the cosine gate.  The
 * weight is the inverse variance of res under the depth noise
 * sigma_z(z)^2 = k2 z^4 + q2 along both rays (the incidence taken as at
 * most 60 degrees: the noise grows at grazing angles), times Tukey's biweight of
 * e = res / sigma with its cut `tukey_c` (a pair beyond it is refused: an
 * occlusion, a moved object).
 */
#ifndef DAO_MOTION_ICP_PAIRS_H
#define DAO_MOTION_ICP_PAIRS_H

#include <stddef.h>

/* source points are handed to the kernels in chunks of this many (the
 * reduction's unit: the sums do not depend on the number of threads) */
#define DAO_ICP_CHUNK 512
/* the source arrays are padded with zeros to a multiple of this */
#define DAO_ICP_PAD 16

struct dao_icp_step {
	const float *tz;  /* target depth, m (0 = none), w x h */
	int w, h, r;      /* size; the normals' radius */
	float ax, bx, ay, by, inv_ax, inv_ay; /* pixel -> ray: x ax + bx */
	const float *src; /* SoA x, y, z, nx, ny, nz, each `cap` floats */
	size_t cap;
	float R[9], t[3];
	float inv_scale;  /* rotation columns of the Jacobian times this */
	float gate2;      /* |d|^2 above this refused */
	float cos_gate;
	float k2, q2;     /* the depth noise: sigma_z^2 = k2 z^4 + q2 */
	float tukey_c;    /* biweight cut of res / sigma */
	int noise_weight; /* 1: the weight is biweight / sigma^2; 0: the biweight alone
			   * (the geometry's conditioning) */
	float edge;       /* a target neighbour at r px off by more than edge r z: a depth
			   * edge, no pair */
};

struct dao_icp_sums {
	double a[21];     /* upper triangle of J^T W J, row by row */
	double b[6];      /* -J^T W res */
	double r2;        /* sum of res^2 (m^2) */
	double e2w, wsum; /* sum of biweight * e^2, of biweight */
	int n;            /* pairs */
};

typedef void (*dao_icp_pairs_fn)(const struct dao_icp_step *st, int i0, int i1,
				 struct dao_icp_sums *out);

void dao_icp_pairs_ref(const struct dao_icp_step *st, int i0, int i1, struct dao_icp_sums *out);

#define DAO_ICP_PAIRS_PROTO(isa)                                                              \
	void dao_icp_pairs_##isa(const struct dao_icp_step *st, int i0, int i1,              \
				 struct dao_icp_sums *out)
DAO_ICP_PAIRS_PROTO(generic);
DAO_ICP_PAIRS_PROTO(sse41);
DAO_ICP_PAIRS_PROTO(avx2);
DAO_ICP_PAIRS_PROTO(avx512);

#endif
