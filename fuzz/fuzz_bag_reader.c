/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is a ROS bag.  It is read twice: with the
 * bag reader alone (every message of every topic, each parsed as an Image,
 * a CameraInfo and a Float32), then as the built-in "bag" source (every
 * frame of the depth topic it picks, one seek back), and where the bytes
 * hold "/imu" once more with pose_topic=/imu (a sensor_msgs/Imu topic's
 * rotation for the poses).  Any outcome is fine except a crash, a sanitizer
 * report, an error without a message, or an error code the source does not
 * document.
 */
#define _GNU_SOURCE /* memmem */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bag/bag_reader.h"
#include "bag/ros_msg.h"
#include "harness.h"

/* Images larger than this are refused by the source (and chunks above 8 x this + 16 MiB). */
#define MAX_PIXELS (1024u * 1024u)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static struct fuzz_file file;
static const int codes[] = { -EINVAL, -EIO, -ENOMEM, -ENOENT, -EACCES, -EFBIG, 0 };

static void read_raw(void)
{
	struct dao_bag *b = NULL;
	struct dao_error err = {0};
	int ret = dao_bag_open(file.path, 8ull * MAX_PIXELS + (16u << 20), &b, &err);
	if (ret < 0) {
		if (b)
			abort();
		fuzz_check_error(ret, &err, codes);
		return;
	}
	for (uint32_t t = 0; t < dao_bag_topic_count(b); t++) {
		const struct dao_bag_topic *tp = dao_bag_topic(b, t);
		if (!tp || !tp->name || !tp->type)
			abort();
		for (uint32_t i = 0; i <= tp->message_count; i++) {
			const uint8_t *d;
			uint32_t n;
			uint64_t ns;
			err.message[0] = 0;
			ret = dao_bag_read_message(b, t, i, &d, &n, &ns, &err);
			if (ret < 0) {
				fuzz_check_error(ret, &err, codes);
				continue;
			}
			if (i == tp->message_count)
				abort(); /* one past the end must fail */
			struct dao_ros_image img;
			struct dao_ros_camera_info ci;
			float v;
			if (dao_ros_image_parse(d, n, &img) == 0 && img.data_len &&
			    (img.data < d || img.data + img.data_len > d + n))
				abort(); /* the pixels lie inside the message */
			(void)dao_ros_camera_info_parse(d, n, &ci);
			(void)dao_ros_float32_parse(d, n, &v);
		}
	}
	if (dao_bag_topic(b, dao_bag_topic_count(b)) != NULL)
		abort();
	dao_bag_close(b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	fuzz_file_store(&file, "fuzz.bag", "bag", data, size);
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
