/* SPDX-License-Identifier: MIT */
/*
 * The synthetic scenes.  World frame: right-handed, z up, floor at z = 0,
 * metres.  Each scene places a look-at camera; the primitives are then
 * moved into the camera's optical frame (x right, y down, z forward).
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/rng.h"
#include "synth/synth.h"

#define DEG (3.14159265358979323846 / 180.0)

static const char *const names[] = {
	"plane", "room-corner", "spheres", "stairs", "boxes", "thin-pole",
	"thin-poles", "chair", "floating-plate", "pole-gaps", "table-above", "pole-widths",
	"shelves-below", "panels", "chair-corner", NULL,
};

const char *const *synth_scene_names(void)
{
	return names;
}

void synth_default_camera(struct dao_camera *cam)
{
	dao_camera_from_intrinsics(cam, 640, 480, 525.0, 525.0, 319.5, 239.5, NULL);
}

static struct synth_prim *add(struct synth_scene *s)
{
	struct synth_prim *p = &s->prims[s->count++];
	memset(p, 0, sizeof *p);
	return p;
}

/* Half-space whose surface passes through c with outward normal n. */
static void halfspace(struct synth_scene *s, vec3 c, vec3 n)
{
	struct synth_prim *p = add(s);
	p->kind = SYNTH_HALFSPACE;
	p->c = c;
	p->n = v3_normalize(n);
}

static void sphere(struct synth_scene *s, vec3 c, double r)
{
	struct synth_prim *p = add(s);
	p->kind = SYNTH_SPHERE;
	p->c = c;
	p->r = r;
}

/* Box with half extents `half`, turned by `yaw_deg` about the vertical axis. */
static void box(struct synth_scene *s, vec3 c, vec3 half, double yaw_deg)
{
	struct synth_prim *p = add(s);
	double a = yaw_deg * DEG;
	p->kind = SYNTH_BOX;
	p->c = c;
	p->half = half;
	p->axis[0] = v3(cos(a), sin(a), 0);
	p->axis[1] = v3(-sin(a), cos(a), 0);
	p->axis[2] = v3(0, 0, 1);
}

/* A sphere of radius r resting on the floor at (c.x, c.y). */
static void sphere_on_floor(struct synth_scene *s, vec3 c, double r)
{
	sphere(s, v3(c.x, c.y, r), r);
}

/* A box with half extents `half` standing on the floor at (c.x, c.y). */
static void box_on_floor(struct synth_scene *s, vec3 c, vec3 half, double yaw_deg)
{
	box(s, v3(c.x, c.y, half.z), half, yaw_deg);
}

/* Box spanning [lo, hi] on each world axis. */
static void box_span(struct synth_scene *s, vec3 lo, vec3 hi)
{
	box(s, v3_scale(v3_add(lo, hi), 0.5), v3_scale(v3_sub(hi, lo), 0.5), 0.0);
}

static void cylinder(struct synth_scene *s, vec3 c, vec3 axis, double r, double half_len)
{
	struct synth_prim *p = add(s);
	p->kind = SYNTH_CYLINDER;
	p->c = c;
	p->n = v3_normalize(axis);
	p->r = r;
	p->h = half_len;
}

/* Moves every primitive into the optical frame of a camera at `eye` looking at `target`. */
static void look_at(struct synth_scene *s, vec3 eye, vec3 target)
{
	vec3 f = v3_normalize(v3_sub(target, eye));
	vec3 right = v3_normalize(v3_cross(f, v3(0, 0, 1)));
	vec3 down = v3_cross(f, right);
	const vec3 R[3] = { right, down, f };
	for (int i = 0; i < s->count; i++)
		synth_prim_transform(&s->prims[i], R, eye);
}

static void floor_plane(struct synth_scene *s)
{
	halfspace(s, v3(0, 0, 0), v3(0, 0, 1));
}

/* A wall facing the camera (-y) at y = d. */
static void back_wall(struct synth_scene *s, double d)
{
	halfspace(s, v3(0, d, 0), v3(0, -1, 0));
}

/*
 * Perturbations of a scene variant: variant 0 is the scene as written; any
 * other variant draws, deterministically from the scene's name and the
 * variant number, a camera moved by up to 15 cm (and its target by 10 cm),
 * objects moved by up to 8 cm on the floor, sizes scaled by 0.85..1.15 and
 * walls moved by up to 20 cm.
 */
struct jitter {
	int on;
	uint64_t rng;
};

static double jit_uniform(struct jitter *j)
{
	return j->on ? 2.0 * synth_rng_uniform(&j->rng) - 1.0 : 0.0;
}

/* A position moved by up to `a` m along each of x and y (z kept: objects stay on the floor). */
static vec3 J(struct jitter *j, vec3 p, double a)
{
	double dx = jit_uniform(j) * a, dy = jit_uniform(j) * a;
	return v3(p.x + dx, p.y + dy, p.z);
}

/* A length scaled by up to +-15 %. */
static double S(struct jitter *j, double x)
{
	return x * (1.0 + 0.15 * jit_uniform(j));
}

static vec3 S3(struct jitter *j, vec3 h)
{
	double k = 1.0 + 0.15 * jit_uniform(j);
	return v3_scale(h, k);
}

/* A distance moved by up to `a` m. */
static double D(struct jitter *j, double x, double a)
{
	return x + a * jit_uniform(j);
}

/* The camera: eye by up to 15 cm in every axis, target by 10 cm. */
static void look_at_j(struct synth_scene *s, struct jitter *j, vec3 eye, vec3 target)
{
	eye = v3(D(j, eye.x, 0.15), D(j, eye.y, 0.15), D(j, eye.z, 0.15));
	target = v3(D(j, target.x, 0.1), D(j, target.y, 0.1), D(j, target.z, 0.1));
	look_at(s, eye, target);
}

int synth_scene_build(const char *name, double t, struct synth_scene *s, struct dao_error *err)
{
	return synth_scene_build_variant(name, t, 0, s, err);
}

static void scene_plane(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "a tilted plane (ground truth 1 everywhere)";
	floor_plane(s);
	look_at_j(s, j, v3(0, 0, 2.0), v3(0.8, 1.0, 0.0));
}

static void scene_room_corner(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "the inside corner of a room: floor, two walls, ceiling";
	floor_plane(s);
	halfspace(s, v3(0, 0, 0), v3(1, 0, 0));
	halfspace(s, v3(0, 0, 0), v3(0, 1, 0));
	halfspace(s, v3(0, 0, D(j, 2.6, 0.2)), v3(0, 0, -1));
	look_at_j(s, j, v3(2.1, 2.3, 1.5), v3(0, 0, 0.7));
}

static void scene_spheres(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "spheres resting on a floor in front of a wall";
	floor_plane(s);
	back_wall(s, D(j, 3.2, 0.2));
	sphere_on_floor(s, J(j, v3(-0.5, 1.6, 0), 0.08), S(j, 0.3));
	sphere_on_floor(s, J(j, v3(0.35 + 0.4 * t, 1.3, 0), 0.08), S(j, 0.18));
	sphere_on_floor(s, J(j, v3(0.6, 2.1, 0), 0.08), S(j, 0.4));
	sphere_on_floor(s, J(j, v3(-0.15, 1.0, 0), 0.08), S(j, 0.1));
	sphere_on_floor(s, J(j, v3(-0.9, 2.5, 0), 0.08), S(j, 0.25));
	look_at_j(s, j, v3(0, -0.3, 1.3), v3(0, 1.8, 0.2));
}

static void scene_stairs(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "a flight of six stairs beside a wall";
	floor_plane(s);
	const double rise = S(j, 0.18), run = S(j, 0.3), y0 = D(j, 1.0, 0.1);
	const double width = S(j, 1.6);
	back_wall(s, 3.5);
	halfspace(s, v3(-0.9, 0, 0), v3(1, 0, 0));
	for (int i = 0; i < 6; i++)
		box_span(s, v3(-0.9, y0 + run * i, 0), v3(-0.9 + width, 3.5, rise * (i + 1)));
	look_at_j(s, j, v3(1.2, -0.6, 1.7), v3(-0.1, 1.9, 0.5));
}

static void scene_boxes(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "cluttered boxes with depth discontinuities";
	floor_plane(s);
	back_wall(s, D(j, 3.0, 0.2));
	box_on_floor(s, J(j, v3(-0.6, 1.5, 0), 0.08), S3(j, v3(0.25, 0.2, 0.25)), 20);
	box_on_floor(s, J(j, v3(0.2, 1.2, 0), 0.08), S3(j, v3(0.15, 0.3, 0.15)), -35);
	{
		/* a box and the one on top of it */
		vec3 c = J(j, v3(0.7, 2.0, 0), 0.08), hb = S3(j, v3(0.3, 0.3, 0.4));
		box_on_floor(s, c, hb, 10);
		box(s, v3(c.x - 0.05, c.y, 2.0 * hb.z + 0.15), v3(0.15, 0.15, 0.15), 40);
	}
	box_on_floor(s, J(j, v3(-0.2, 2.4, 0), 0.08), S3(j, v3(0.4, 0.15, 0.2)), 0);
	box_on_floor(s, J(j, v3(0.0, 0.8, 0), 0.08), S3(j, v3(0.08, 0.08, 0.06)), 30);
	box_on_floor(s, J(j, v3(-1.0, 2.6, 0), 0.08), S3(j, v3(0.2, 0.2, 0.5)), 15);
	look_at_j(s, j, v3(0, -0.6, 1.5), v3(0, 1.6, 0.3));
}

static void scene_thin_pole(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "a thin pole in front of a wall";
	floor_plane(s);
	back_wall(s, D(j, 3.0, 0.15));
	cylinder(s, J(j, v3(0.0 + 0.3 * t, 2.72, 1.0), 0.06), v3(0, 0, 1), S(j, 0.025), 1.0);
	look_at_j(s, j, v3(0.3, 0.3, 1.2), v3(0, 3.0, 0.9));
}

static void scene_thin_poles(struct synth_scene *s, struct jitter *j, double t)
{
	/* thickness stress: what is behind a thin object is lit */
	s->description = "a row of thin poles in front of a wall";
	floor_plane(s);
	back_wall(s, D(j, 3.0, 0.15));
	for (int i = 0; i < 5; i++)
		cylinder(s, J(j, v3(-0.8 + 0.4 * i + 0.2 * t, 2.4 + 0.1 * (i % 2), 0.9), 0.05),
			 v3(0, 0, 1), S(j, 0.02), 0.9);
	look_at_j(s, j, v3(0.1, 0.0, 1.3), v3(0, 3.0, 0.8));
}

static void scene_chair(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "a chair-like frame: four thin legs, a seat and a back";
	floor_plane(s);
	back_wall(s, D(j, 3.2, 0.15));
	const double cx = D(j, 0.1, 0.08) + 0.3 * t, cy = D(j, 2.0, 0.08);
	for (int i = 0; i < 4; i++)
		box(s, v3(cx + (i & 1 ? 0.2 : -0.2), cy + (i & 2 ? 0.2 : -0.2), 0.225),
		    v3(0.02, 0.02, 0.225), 0);
	box(s, v3(cx, cy, 0.47), v3(0.24, 0.24, 0.025), 0);
	box(s, v3(cx, cy + 0.22, 0.75), v3(0.24, 0.02, 0.26), 0);
	look_at_j(s, j, v3(0.6, 0.2, 1.4), v3(0.1, 2.2, 0.3));
}

static void scene_floating_plate(struct synth_scene *s, struct jitter *j, double t)
{
	s->description = "a thin plate floating above the floor";
	floor_plane(s);
	back_wall(s, D(j, 3.4, 0.15));
	box(s, v3(0.0, 1.8, D(j, 0.35, 0.05) + 0.2 * t), S3(j, v3(0.4, 0.3, 0.01)), 25);
	look_at_j(s, j, v3(0.4, -0.2, 1.6), v3(0, 1.9, 0.2));
}

static void scene_pole_gaps(struct synth_scene *s, struct jitter *j, double t)
{
	/* thickness: the same 4 cm pole 5 cm to 1 m in front of the wall behind it */
	static const double gap[5] = { 0.05, 0.15, 0.3, 0.6, 1.0 };
	s->description = "five 4 cm poles 5 cm to 1 m in front of a wall";
	floor_plane(s);
	const double wall = D(j, 3.0, 0.15), r = S(j, 0.02);
	back_wall(s, wall);
	for (int i = 0; i < 5; i++)
		cylinder(s, J(j, v3(-1.0 + 0.5 * i + 0.2 * t, wall - gap[i] - r, 0.9), 0.02),
			 v3(0, 0, 1), r, 0.9);
	look_at_j(s, j, v3(0.0, 0.0, 1.3), v3(0, 3.0, 0.8));
}

static void scene_pole_widths(struct synth_scene *s, struct jitter *j, double t)
{
	/* thickness: poles 1 to 20 cm wide, 30 cm in front of the wall */
	static const double diam[5] = { 0.01, 0.02, 0.05, 0.1, 0.2 };
	s->description = "five poles 1 to 20 cm wide, 30 cm in front of a wall";
	floor_plane(s);
	const double wall = D(j, 3.0, 0.15);
	back_wall(s, wall);
	for (int i = 0; i < 5; i++) {
		const double r = 0.5 * S(j, diam[i]);
		cylinder(s, J(j, v3(-1.0 + 0.5 * i + 0.2 * t, wall - 0.3 - r, 0.9), 0.02),
			 v3(0, 0, 1), r, 0.9);
	}
	look_at_j(s, j, v3(0.1, 0.0, 1.3), v3(0, 3.0, 0.8));
}

static void scene_table_above(struct synth_scene *s, struct jitter *j, double t)
{
	/* thickness: table tops seen from above, 3 cm and 8 cm thick, on thin legs */
	s->description = "a table (3 cm top) and a low bench (8 cm top) seen from above";
	floor_plane(s);
	back_wall(s, D(j, 3.4, 0.15));
	const vec3 c = J(j, v3(-0.2 + 0.3 * t, 1.9, 0), 0.08);
	const double top = D(j, 0.72, 0.05), th = S(j, 0.03);
	box(s, v3(c.x, c.y, top - 0.5 * th), v3(0.5, 0.3, 0.5 * th), 5);
	for (int i = 0; i < 4; i++)
		box_on_floor(s, v3(c.x + (i & 1 ? 0.45 : -0.45), c.y + (i & 2 ? 0.25 : -0.25), 0),
			     v3(0.02, 0.02, 0.5 * (top - th)), 5);
	const vec3 b = J(j, v3(0.75, 1.4, 0), 0.08);
	const double bt = S(j, 0.08), bh = D(j, 0.4, 0.05);
	box(s, v3(b.x, b.y, bh - 0.5 * bt), v3(0.35, 0.2, 0.5 * bt), -20);
	box_on_floor(s, v3(b.x, b.y, 0), v3(0.03, 0.12, 0.5 * (bh - bt)), -20);
	look_at_j(s, j, v3(0.6, -0.3, 2.0), v3(0.1, 1.8, 0.3));
}

static void scene_shelves_below(struct synth_scene *s, struct jitter *j, double t)
{
	/* thickness: 2 cm shelf boards seen from below, 25 cm in front of a wall */
	s->description = "a shelf unit (2 cm boards) seen from below";
	floor_plane(s);
	const double wall = D(j, 3.0, 0.15), th = S(j, 0.02), depth = 0.35;
	back_wall(s, wall);
	const double y = wall - 0.25 - 0.5 * depth, x0 = D(j, 0.0, 0.08);
	for (int i = 0; i < 2; i++)
		box(s, v3(x0 + (i ? 0.41 : -0.41), y, 0.8), v3(0.5 * th, 0.5 * depth, 0.8), 0);
	for (int i = 0; i < 4; i++)
		box(s, v3(x0, y, D(j, 0.5 + 0.37 * i, 0.03)), v3(0.4, 0.5 * depth, 0.5 * th), 0);
	look_at_j(s, j, v3(0.35, 0.6, 0.35), v3(0.0, 2.7, 1.1));
}

static void scene_panels(struct synth_scene *s, struct jitter *j, double t)
{
	/* thickness: upright boards 1, 5 and 20 cm thick, turned, seen mostly face on */
	static const double thick[3] = { 0.01, 0.05, 0.2 };
	s->description = "three upright boards 1, 5 and 20 cm thick in front of a wall";
	floor_plane(s);
	back_wall(s, D(j, 3.2, 0.15));
	for (int i = 0; i < 3; i++)
		box_on_floor(s, J(j, v3(-0.8 + 0.8 * i + 0.2 * t, 2.2 + 0.2 * i, 0), 0.06),
			     v3(0.3, 0.5 * S(j, thick[i]), 0.5), 30 - 20 * i);
	look_at_j(s, j, v3(0.2, -0.1, 1.4), v3(0, 3.0, 0.5));
}

static void scene_chair_corner(struct synth_scene *s, struct jitter *j, double t)
{
	/* thickness: the chair in the corner of a room, its back 25 cm from a wall */
	s->description = "a chair-like frame in the corner of a room";
	floor_plane(s);
	halfspace(s, v3(0, 0, 0), v3(1, 0, 0));
	halfspace(s, v3(0, 0, 0), v3(0, 1, 0));
	const double cx = D(j, 0.6, 0.06) + 0.3 * t, cy = D(j, 0.55, 0.06);
	for (int i = 0; i < 4; i++)
		box(s, v3(cx + (i & 1 ? 0.2 : -0.2), cy + (i & 2 ? 0.2 : -0.2), 0.225),
		    v3(0.02, 0.02, 0.225), 0);
	box(s, v3(cx, cy, 0.47), v3(0.24, 0.24, 0.025), 0);
	box(s, v3(cx, cy - 0.22, 0.75), v3(0.24, 0.02, 0.26), 0);
	look_at_j(s, j, v3(2.1, 2.3, 1.5), v3(0.3, 0.3, 0.4));
}

/* Each scene places its primitives and its camera; t in [0, 1] moves its object in a sequence. */
struct scene_builder {
	const char *name;
	void (*build)(struct synth_scene *s, struct jitter *j, double t);
};

static const struct scene_builder builders[] = {
	{ "plane", scene_plane },
	{ "room-corner", scene_room_corner },
	{ "spheres", scene_spheres },
	{ "stairs", scene_stairs },
	{ "boxes", scene_boxes },
	{ "thin-pole", scene_thin_pole },
	{ "thin-poles", scene_thin_poles },
	{ "chair", scene_chair },
	{ "floating-plate", scene_floating_plate },
	{ "pole-gaps", scene_pole_gaps },
	{ "pole-widths", scene_pole_widths },
	{ "table-above", scene_table_above },
	{ "shelves-below", scene_shelves_below },
	{ "panels", scene_panels },
	{ "chair-corner", scene_chair_corner },
};

static const struct scene_builder *scene_builder(const char *name)
{
	for (size_t i = 0; i < sizeof builders / sizeof builders[0]; i++)
		if (strcmp(builders[i].name, name) == 0)
			return &builders[i];
	return NULL;
}

int synth_scene_build_variant(const char *name, double t, int variant, struct synth_scene *s,
			      struct dao_error *err)
{
	memset(s, 0, sizeof *s);
	struct jitter jj = { variant != 0, 0x7363656e65ull + (uint64_t)variant * 0x9e3779b97f4a7c15ull };
	for (const char *c = name ? name : ""; *c; c++)
		jj.rng = (jj.rng ^ (uint8_t)*c) * 0x100000001b3ull;
	if (!name)
		name = "";
	if (!(t >= 0.0 && t <= 1.0))
		t = 0.0;
	const struct scene_builder *b = scene_builder(name);
	if (!b)
		return dao_error_set(err, -EINVAL,
				     "unknown scene '%s': use plane, room-corner, spheres, stairs, "
				     "boxes, thin-pole, thin-poles, chair, floating-plate, pole-gaps, "
				     "table-above, pole-widths, shelves-below, panels or chair-corner", name);
	b->build(s, &jj, t);
	s->name = name;
	for (const char *const *n = names; *n; n++)
		if (strcmp(*n, name) == 0)
			s->name = *n;
	return 0;
}
