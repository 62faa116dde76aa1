/* SPDX-License-Identifier: MIT */
/*
 * A scene with a closed-form AO: a floor 2 m below a camera looking straight
 * down, and a wall (x = +0.3 m) through the whole view.  For a floor point at
 * distance d from the wall, rays hit the wall within R when their tangential
 * x component exceeds d/R; with cosine-weighted directions that component is
 * distributed as x of a uniform point on the unit disk, so
 *   visibility = 1 - (acos a - a sqrt(1 - a^2)) / pi,   a = d/R.
 */
#ifndef DAO_TEST_FLOOR_WALL_H
#define DAO_TEST_FLOOR_WALL_H

#include "synth/synth.h"

#define FLOOR_WALL_DEPTH 2.0 /* m, floor below the camera */
#define FLOOR_WALL_X 0.3     /* m, the wall's plane */

void floor_wall_scene(struct synth_scene *s);

/* Exact visibility of the floor point at lateral position x (m) for radius R. */
double floor_wall_visibility(double x, double radius);

#endif
