/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is a camera file.  It is parsed as a ROS
 * CameraInfo YAML document (camera_info_yaml_parse(), libyaml's document API
 * and the checks on it) and read as a file by camera_file_load(), which picks
 * YAML or Open3D JSON by its first character.  Any outcome is fine except a
 * crash, a sanitizer report, an error without a message, or a camera that
 * dao_camera_from_intrinsics() would refuse.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "common/camera_file.h"
#include "common/camera_info_yaml.h"
#include "harness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct camera_info ci;
	char msg[512], warning[640];
	msg[0] = '\0';
	if (camera_info_yaml_parse((const char *)data, size, "fuzz", &ci, msg, sizeof msg)) {
		if (!msg[0])
			abort();
	} else if (ci.width == 0 || ci.height == 0 || ci.nd > CAMERA_INFO_MAX_DISTORTION ||
		   ci.k[8] != 1) {
		abort();
	}

	static struct fuzz_file file;
	fuzz_file_store(&file, "fuzz-camera", NULL, data, size);
	struct dao_camera cam;
	msg[0] = '\0';
	if (camera_file_load(file.path, &cam, warning, sizeof warning, msg, sizeof msg)) {
		if (!msg[0])
			abort();
	} else if (!(cam.fx > 0 && cam.fy > 0 && isfinite(cam.cx) && isfinite(cam.cy))) {
		abort();
	}
	return 0;
}
