/* SPDX-License-Identifier: MIT */
/*
 * Camera intrinsics files: Open3D's PinholeCameraIntrinsic JSON
 *   { "width": 640, "height": 480,
 *     "intrinsic_matrix": [fx, 0, 0, 0, fy, 0, cx, cy, 1] }   (column-major K)
 * as used by the Redwood and RealSense data in ../shared/data, and ROS
 * CameraInfo YAML (camera_info_manager's format, camera_info_yaml.h).  A
 * name ending in .yaml/.yml is YAML, .json JSON, else a file starting with
 * '{' is JSON and any other YAML.
 */
#ifndef DAO_TOOLS_CAMERA_FILE_H
#define DAO_TOOLS_CAMERA_FILE_H

#include <depthao/camera.h>

struct json_object;

/*
 * Reads a camera file.  On error returns -1 with a message naming the file and
 * the problem.  `warning` (may be NULL) gets what the caller should tell the
 * user, or "": a CameraInfo with distortion (the depth must be rectified; its
 * projection matrix's intrinsics are used then), a skewed K.
 */
int camera_file_load(const char *path, struct dao_camera *cam, char *warning, size_t wlen,
		     char *msg, size_t len);

/* camera_file_load() that prints the warning to stderr ("depthao: warning: ..."). */
int camera_file_read(const char *path, struct dao_camera *cam, char *msg, size_t len);

/*
 * The camera file beside PNG input, where depthao process and depthaod both
 * look for it when nothing else gives the intrinsics (a recording's own come
 * first): camera.json, else camera.yaml (a ROS CameraInfo), in `path` when it
 * is a directory, or in the directory of `path` when it names a .png file (any
 * case); not beside other files (a recording's directory may hold another
 * camera's file).  1 with its path in `out` (`len` bytes); -1 with its path in
 * `out`: the first of them there cannot be read (errno says why: tell the
 * user, rather than run with a default camera); 0: neither is there, or
 * `path` is not PNG input (or its directory's name does not fit in `out`).
 */
int camera_file_beside(const char *path, char *out, size_t len);

/*
 * Writes a camera file atomically (temp file + rename); `extra` (may be NULL)
 * is an object whose keys are added.  Returns 0 or -1 with a message.
 */
int camera_file_write(const char *path, const struct dao_camera *cam, struct json_object *extra,
		      char *msg, size_t len);

#endif
