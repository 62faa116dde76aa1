/* SPDX-License-Identifier: MIT */
/*
 * Camera intrinsics files in Open3D's PinholeCameraIntrinsic JSON format:
 *   { "width": 640, "height": 480,
 *     "intrinsic_matrix": [fx, 0, 0, 0, fy, 0, cx, cy, 1] }   (column-major K)
 * as used by the Redwood and RealSense data in ../shared/data.
 */
#ifndef DAO_TOOLS_CAMERA_FILE_H
#define DAO_TOOLS_CAMERA_FILE_H

#include <depthao/camera.h>

struct json_object;

/* Reads a camera file.  On error returns -1 with a message naming the file and the problem. */
int camera_file_read(const char *path, struct dao_camera *cam, char *msg, size_t len);

/*
 * Writes a camera file atomically (temp file + rename); `extra` (may be NULL)
 * is an object whose keys are added.  Returns 0 or -1 with a message.
 */
int camera_file_write(const char *path, const struct dao_camera *cam, struct json_object *extra,
		      char *msg, size_t len);

#endif
