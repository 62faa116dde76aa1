/* SPDX-License-Identifier: MIT */
/*
 * The synthetic scenes.  World frame: right-handed, z up, floor at z = 0,
 * metres.  Each scene places a look-at camera; the primitives are then
 * moved into the camera's optical frame (x right, y down, z forward).
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "core/error_internal.h"
#include "synth/synth.h"

#define DEG (3.14159265358979323846 / 180.0)

static const char *const names[] = {
	"plane", "room-corner", "spheres", "stairs", "boxes", "thin-pole",
	"thin-poles", "chair", "floating-plate", NULL,
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

int synth_scene_build(const char *name, double t, struct synth_scene *s, struct dao_error *err)
{
	memset(s, 0, sizeof *s);
	if (!name)
		name = "";
	if (!(t >= 0.0 && t <= 1.0))
		t = 0.0;
	if (strcmp(name, "plane") == 0) {
		s->description = "a tilted plane (ground truth 1 everywhere)";
		floor_plane(s);
		look_at(s, v3(0, 0, 2.0), v3(0.8, 1.0, 0.0));
	} else if (strcmp(name, "room-corner") == 0) {
		s->description = "the inside corner of a room: floor, two walls, ceiling";
		floor_plane(s);
		halfspace(s, v3(0, 0, 0), v3(1, 0, 0));
		halfspace(s, v3(0, 0, 0), v3(0, 1, 0));
		halfspace(s, v3(0, 0, 2.6), v3(0, 0, -1));
		look_at(s, v3(2.1, 2.3, 1.5), v3(0, 0, 0.7));
	} else if (strcmp(name, "spheres") == 0) {
		s->description = "spheres resting on a floor in front of a wall";
		floor_plane(s);
		back_wall(s, 3.2);
		sphere(s, v3(-0.5, 1.6, 0.3), 0.3);
		sphere(s, v3(0.35 + 0.4 * t, 1.3, 0.18), 0.18);
		sphere(s, v3(0.6, 2.1, 0.4), 0.4);
		sphere(s, v3(-0.15, 1.0, 0.1), 0.1);
		sphere(s, v3(-0.9, 2.5, 0.25), 0.25);
		look_at(s, v3(0, -0.3, 1.3), v3(0, 1.8, 0.2));
	} else if (strcmp(name, "stairs") == 0) {
		s->description = "a flight of six stairs beside a wall";
		floor_plane(s);
		back_wall(s, 3.5);
		halfspace(s, v3(-0.9, 0, 0), v3(1, 0, 0));
		for (int i = 0; i < 6; i++)
			box_span(s, v3(-0.9, 1.0 + 0.3 * i, 0), v3(0.7, 3.5, 0.18 * (i + 1)));
		look_at(s, v3(1.2, -0.6, 1.7), v3(-0.1, 1.9, 0.5));
	} else if (strcmp(name, "boxes") == 0) {
		s->description = "cluttered boxes with depth discontinuities";
		floor_plane(s);
		back_wall(s, 3.0);
		box(s, v3(-0.6, 1.5, 0.25), v3(0.25, 0.2, 0.25), 20);
		box(s, v3(0.2, 1.2, 0.15), v3(0.15, 0.3, 0.15), -35);
		box(s, v3(0.7, 2.0, 0.4), v3(0.3, 0.3, 0.4), 10);
		box(s, v3(0.65, 2.0, 0.95), v3(0.15, 0.15, 0.15), 40);
		box(s, v3(-0.2, 2.4, 0.2), v3(0.4, 0.15, 0.2), 0);
		box(s, v3(0.0, 0.8, 0.06), v3(0.08, 0.08, 0.06), 30);
		box(s, v3(-1.0, 2.6, 0.5), v3(0.2, 0.2, 0.5), 15);
		look_at(s, v3(0, -0.6, 1.5), v3(0, 1.6, 0.3));
	} else if (strcmp(name, "thin-pole") == 0) {
		s->description = "a thin pole in front of a wall";
		floor_plane(s);
		back_wall(s, 3.0);
		cylinder(s, v3(0.0 + 0.3 * t, 2.72, 1.0), v3(0, 0, 1), 0.025, 1.0);
		look_at(s, v3(0.3, 0.3, 1.2), v3(0, 3.0, 0.9));
	} else if (strcmp(name, "thin-poles") == 0) {
		/* thickness stress: what is behind a thin object is lit */
		s->description = "a row of thin poles in front of a wall";
		floor_plane(s);
		back_wall(s, 3.0);
		for (int i = 0; i < 5; i++)
			cylinder(s, v3(-0.8 + 0.4 * i + 0.2 * t, 2.4 + 0.1 * (i % 2), 0.9), v3(0, 0, 1),
				 0.02, 0.9);
		look_at(s, v3(0.1, 0.0, 1.3), v3(0, 3.0, 0.8));
	} else if (strcmp(name, "chair") == 0) {
		s->description = "a chair-like frame: four thin legs, a seat and a back";
		floor_plane(s);
		back_wall(s, 3.2);
		const double cx = 0.1 + 0.3 * t, cy = 2.0;
		for (int i = 0; i < 4; i++)
			box(s, v3(cx + (i & 1 ? 0.2 : -0.2), cy + (i & 2 ? 0.2 : -0.2), 0.225),
			    v3(0.02, 0.02, 0.225), 0);
		box(s, v3(cx, cy, 0.47), v3(0.24, 0.24, 0.025), 0);
		box(s, v3(cx, cy + 0.22, 0.75), v3(0.24, 0.02, 0.26), 0);
		look_at(s, v3(0.6, 0.2, 1.4), v3(0.1, 2.2, 0.3));
	} else if (strcmp(name, "floating-plate") == 0) {
		s->description = "a thin plate floating above the floor";
		floor_plane(s);
		back_wall(s, 3.4);
		box(s, v3(0.0, 1.8, 0.35 + 0.2 * t), v3(0.4, 0.3, 0.01), 25);
		look_at(s, v3(0.4, -0.2, 1.6), v3(0, 1.9, 0.2));
	} else {
		return dao_error_set(err, -EINVAL,
				     "unknown scene '%s': use plane, room-corner, spheres, stairs, "
				     "boxes, thin-pole, thin-poles, chair or floating-plate", name);
	}
	s->name = name;
	for (const char *const *n = names; *n; n++)
		if (strcmp(*n, name) == 0)
			s->name = *n;
	return 0;
}
