/* SPDX-License-Identifier: MIT */
/*
 * ROS CameraInfo calibration files, as camera_info_manager and
 * camera_calibration write them (YAML, read with libyaml):
 *   image_width: 640
 *   image_height: 480
 *   camera_name: depth
 *   camera_matrix: { rows: 3, cols: 3, data: [fx, 0, cx, 0, fy, cy, 0, 0, 1] }  (row-major K)
 *   distortion_model: plumb_bob
 *   distortion_coefficients: { rows: 1, cols: 5, data: [k1, k2, t1, t2, k3] }
 *   rectification_matrix: { rows: 3, cols: 3, data: [...] }
 *   projection_matrix: { rows: 3, cols: 4, data: [fx', 0, cx', Tx, 0, fy', cy', Ty, 0, 0, 1, 0] }
 */
#ifndef DAO_TOOLS_CAMERA_INFO_YAML_H
#define DAO_TOOLS_CAMERA_INFO_YAML_H

#include <stddef.h>
#include <stdint.h>

#define CAMERA_INFO_MAX_DISTORTION 16

struct camera_info {
	uint32_t width, height;
	char name[128];            /* camera_name, "" if absent */
	char distortion_model[64]; /* "" if absent */
	double k[9];               /* camera_matrix, row-major */
	double d[CAMERA_INFO_MAX_DISTORTION];
	int nd;                    /* distortion coefficients given */
	double r[9];
	int has_r;
	double p[12];              /* projection_matrix, row-major */
	int has_p;
};

/*
 * Parses a CameraInfo YAML document of `len` bytes; `name` (the file) goes
 * into messages.  Checks the structure (rows x cols = the data's length, 3x3
 * K with the last row 0 0 1, numbers finite, sizes 1..DAO_MAX_DIMENSION).
 * Returns 0, or -1 with a message naming `name` and what is wrong (for
 * syntax errors the line and column).
 */
int camera_info_yaml_parse(const char *text, size_t len, const char *name, struct camera_info *ci,
			   char *msg, size_t msglen);

#endif
