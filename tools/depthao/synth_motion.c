/* SPDX-License-Identifier: MIT */
/* depthao synth --trajectory: poses and true depth beside the frames (synth_motion.h). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "file_list.h"
#include "synth_motion.h"

const char *synth_motion_set(int variant)
{
	return variant % 2 ? "heldout" : "tune";
}

uint64_t synth_motion_seed(uint64_t seed, int variant)
{
	return seed * 0x9e3779b97f4a7c15ull ^ ((uint64_t)variant << 32 | 0x6d6f74u);
}

int synth_motion_write_poses(const char *path, const struct synth_trajectory *tr, int frames,
			     double fps, const char *scene, int variant)
{
	FILE *f = fopen(path, "w");
	if (!f) {
		fprintf(stderr, "depthao: cannot create '%s': %s\n", path, strerror(errno));
		return 1;
	}
	int r = fprintf(f,
			"# depthao synth: true camera poses, trajectory %s, scene %s, variant %d (%s set)\n"
			"# camera to world; world = the optical frame of frame 0 (x right, y down, "
			"z forward); metres\n"
			"# timestamp tx ty tz qx qy qz qw\n",
			tr->name, scene, variant, synth_motion_set(variant)) < 0;
	for (int i = 0; i < frames && !r; i++) {
		struct synth_pose p;
		double time = (double)i / fps;
		synth_trajectory_pose(tr, time, &p);
		r = synth_pose_write(f, time, &p) != 0;
	}
	if (fclose(f) || r) {
		fprintf(stderr, "depthao: cannot write '%s'\n", path);
		return 1;
	}
	return 0;
}

int synth_motion_write_depth_gt(const char *dir, int i, const struct synth_image *img,
				struct dao_error *err)
{
	const size_t np = (size_t)img->width * (size_t)img->height;
	uint16_t *mm = malloc(np * sizeof *mm);
	char file[32];
	snprintf(file, sizeof file, "%04d.png", i);
	char *path = path_join(dir, file);
	int r;
	if (!mm || !path) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
	} else {
		for (size_t k = 0; k < np; k++) {
			double z = img->depth[k] * 1000.0;
			mm[k] = z > 0.0 ? (uint16_t)lrint(fmin(z, 65535.0)) : 0;
		}
		struct dao_frame depth = {
			.format = DAO_PIXFMT_DEPTH16, .width = (uint32_t)img->width,
			.height = (uint32_t)img->height, .stride = (int32_t)(2 * img->width),
			.data = mm, .depth_unit = 0.001f,
		};
		r = dao_png_write(path, &depth, err);
	}
	free(mm);
	free(path);
	return r;
}
