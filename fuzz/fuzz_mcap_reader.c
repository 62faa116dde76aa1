/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is an MCAP file.  It is read twice: with the
 * MCAP reader alone (every message of every channel, one past the end,
 * each parsed as a ROS 2 Image, CompressedImage and CameraInfo), then as
 * the built-in "mcap" source (every frame of the depth topic it picks, one
 * seek back), and where the bytes hold "/imu" once more with
 * pose_topic=/imu (a sensor_msgs/msg/Imu topic's rotation for the poses).
 * Any outcome is fine except a crash, a sanitizer report, an error without
 * a message, or an error code the source does not document.
 */
#define _GNU_SOURCE /* memmem */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "mcap/mcap_reader.h"
#include "mcap/ros2_msg.h"

/* Images larger than this are refused by the source (and chunks above 8 x this + 64 MiB). */
#define MAX_PIXELS (1024u * 1024u)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static struct fuzz_file file;
static const int codes[] = { -EINVAL, -EIO, -ENOMEM, -ENOENT, -EACCES, -EFBIG, 0 };

static void read_raw(void)
{
	struct dao_mcap *m = NULL;
	struct dao_error err = {0};
	int ret = dao_mcap_open(file.path, 8ull * MAX_PIXELS + (64u << 20), &m, &err);
	if (ret < 0) {
		if (m)
			abort();
		fuzz_check_error(ret, &err, codes);
		return;
	}
	for (uint32_t t = 0; t < dao_mcap_topic_count(m); t++) {
		const struct dao_mcap_topic *tp = dao_mcap_topic(m, t);
		if (!tp || !tp->name || !tp->schema || !tp->encoding || !tp->schema_encoding)
			abort();
		for (uint32_t i = 0; i <= tp->message_count; i++) {
			const uint8_t *d;
			uint64_t n, ns;
			err.message[0] = 0;
			ret = dao_mcap_read_message(m, t, i, &d, &n, &ns, &err);
			if (ret < 0) {
				fuzz_check_error(ret, &err, codes);
				continue;
			}
			if (i == tp->message_count)
				abort(); /* one past the end must fail */
			struct dao_ros2_image img;
			struct dao_ros2_compressed_image ci;
			struct dao_ros2_camera_info cam;
			if (dao_ros2_image_parse(d, n, &img) == 0 && img.data_len &&
			    (img.data < d || img.data + img.data_len > d + n))
				abort(); /* the pixels lie inside the message */
			if (dao_ros2_compressed_image_parse(d, n, &ci) == 0 && ci.data_len &&
			    (ci.data < d || ci.data + ci.data_len > d + n))
				abort();
			(void)dao_ros2_camera_info_parse(d, n, &cam);
		}
	}
	if (dao_mcap_topic(m, dao_mcap_topic_count(m)) != NULL)
		abort();
	dao_mcap_close(m);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	fuzz_file_store(&file, "fuzz.mcap", "mcap", data, size);
	read_raw();
	fuzz_play_source(file.uri, MAX_PIXELS, 0, codes);
	/* an IMU topic named /imu: played again with it as the poses' (source_poses.c's IMU
	 * path: its messages, the gaps, the mount); only then, to keep the runs fast */
	if (memmem(data, size, "/imu", 4)) {
		char uri[sizeof file.uri + 32];
		snprintf(uri, sizeof uri, "%s?pose_topic=/imu&pose_gap=0.02", file.uri);
		fuzz_play_source(uri, MAX_PIXELS, 0, codes);
	}
	return 0;
}
