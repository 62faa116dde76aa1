/* SPDX-License-Identifier: MIT */
/*
 * Analytic primitives for the synthetic scenes and exact ray intersection.
 * All primitives are convex solids (or half-spaces), so a ray leaving a
 * primitive's surface never hits that primitive again.
 */
#ifndef DAO_SYNTH_GEOMETRY_H
#define DAO_SYNTH_GEOMETRY_H

typedef struct {
	double x, y, z;
} vec3;

static inline vec3 v3(double x, double y, double z)
{
	return (vec3){ x, y, z };
}
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_scale(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
	return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
vec3 v3_normalize(vec3 a);

enum synth_prim_kind {
	SYNTH_HALFSPACE, /* solid on the side opposite to the normal: n.(x - p) <= 0 */
	SYNTH_SPHERE,
	SYNTH_BOX,       /* oriented box: centre, three unit axes, half extents */
	SYNTH_CYLINDER,  /* capped: centre, unit axis, radius, half length */
};

struct synth_prim {
	enum synth_prim_kind kind;
	vec3 c;          /* point on plane / centre */
	vec3 n;          /* plane normal (pointing out of the solid) / cylinder axis */
	vec3 axis[3];    /* box axes */
	vec3 half;       /* box half extents */
	double r, h;     /* sphere or cylinder radius, cylinder half length */
	/* bounding sphere for culling (radius < 0: unbounded) */
	vec3 bc;
	double br;
};

/* Fills the bounding sphere of a primitive. */
void synth_prim_bound(struct synth_prim *p);

/*
 * Nearest intersection of the ray o + t d (d need not be unit) with t in
 * (tmin, tmax).  Returns 1 and sets *t and the outward unit normal *n.
 */
int synth_prim_intersect(const struct synth_prim *p, vec3 o, vec3 d, double tmin, double tmax,
			 double *t, vec3 *n);

/* Applies a rigid transform x' = R (x - eye) (rows of R given) to a primitive. */
void synth_prim_transform(struct synth_prim *p, const vec3 R[3], vec3 eye);

#endif
