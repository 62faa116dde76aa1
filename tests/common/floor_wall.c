/* SPDX-License-Identifier: MIT */
#include <math.h>

#include "common/floor_wall.h"

void floor_wall_scene(struct synth_scene *s)
{
	*s = (struct synth_scene){ .name = "floor-wall", .count = 2 };
	s->prims[0] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 0, FLOOR_WALL_DEPTH },
					   .n = { 0, 0, -1 } };
	s->prims[1] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { FLOOR_WALL_X, 0, 0 },
					   .n = { -1, 0, 0 } };
	synth_prim_bound(&s->prims[0]);
	synth_prim_bound(&s->prims[1]);
}

double floor_wall_visibility(double x, double radius)
{
	double a = (FLOOR_WALL_X - x) / radius;
	if (a >= 1.0)
		return 1.0;
	return 1.0 - (acos(a) - a * sqrt(1.0 - a * a)) / 3.14159265358979323846;
}
