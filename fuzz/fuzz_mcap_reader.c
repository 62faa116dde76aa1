/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is an MCAP file.  It is read twice: with the
 * MCAP reader alone (every message of every channel, one past the end,
 * each parsed as a ROS 2 Image, CompressedImage and CameraInfo), then as
 * the built-in "mcap" source (every frame of the depth topic it picks, one
 * seek back).  Any outcome is fine
 * except a crash, a sanitizer report, an error without a message, or an
 * error code the source does not document.
 */
#define _GNU_SOURCE /* memfd_create */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include <depthao/plugin.h>

#include "mcap/mcap_reader.h"
#include "mcap/ros2_msg.h"

/* Images larger than this are refused by the source (and chunks above 8 x this + 64 MiB). */
#define MAX_PIXELS (1024u * 1024u)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int fd = -1;
static char path[64], uri[80];
static struct dao_plugins *plugins;

static void setup(void)
{
	struct dao_error err;
	if (dao_plugins_load(&plugins, "", &err) < 0)
		abort();
#ifdef MFD_CLOEXEC
	fd = memfd_create("fuzz-mcap", MFD_CLOEXEC);
	if (fd >= 0) {
		snprintf(path, sizeof(path), "/proc/self/fd/%d", fd);
		if (access(path, R_OK) == 0)
			goto done;
		close(fd);
	}
#endif
	snprintf(path, sizeof(path), "/tmp/fuzz-mcap-%ld.mcap", (long)getpid());
	fd = -2; /* plain file, rewritten for every input */
done:
	snprintf(uri, sizeof(uri), "mcap:%s", path);
}

static int store(const uint8_t *d, size_t n)
{
	if (fd >= 0) {
		if (ftruncate(fd, 0) != 0)
			return -1;
		return pwrite(fd, d, n, 0) == (ssize_t)n ? 0 : -1;
	}
	FILE *f = fopen(path, "wb");
	if (!f)
		return -1;
	size_t w = n ? fwrite(d, 1, n, f) : 0;
	return fclose(f) == 0 && w == n ? 0 : -1;
}

static void check_error(int ret, const struct dao_error *err)
{
	if (ret != -EINVAL && ret != -EIO && ret != -ENOMEM && ret != -ENOENT && ret != -EACCES &&
	    ret != -EFBIG)
		abort();
	if (!err->message[0] || err->code != ret)
		abort();
}

static void read_raw(void)
{
	struct dao_mcap *m = NULL;
	struct dao_error err = {0};
	int ret = dao_mcap_open(path, 8ull * MAX_PIXELS + (64u << 20), &m, &err);
	if (ret < 0) {
		if (m)
			abort();
		check_error(ret, &err);
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
				check_error(ret, &err);
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

static void read_source(void)
{
	struct dao_source *s = NULL;
	struct dao_error err = {0};
	int ret = dao_source_open_limited(plugins, uri, NULL, MAX_PIXELS, &s, &err);
	if (ret < 0) {
		if (s)
			abort();
		check_error(ret, &err);
		return;
	}
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	if ((uint64_t)in.width * in.height > MAX_PIXELS || in.frame_count <= 0 ||
	    !memchr(in.description, 0, sizeof(in.description)))
		abort();
	if (dao_source_start(s, &err) < 0)
		abort();
	for (int pass = 0; pass < 2; pass++) {
		for (;;) {
			struct dao_source_frame f;
			err.message[0] = 0;
			ret = dao_source_read(s, &f, 0, &err);
			if (ret == DAO_SOURCE_EOS)
				break;
			if (ret < 0) {
				check_error(ret, &err);
				continue;
			}
			if (f.depth.width != in.width || f.depth.height != in.height ||
			    f.depth.format != in.format)
				abort();
			dao_source_release(s, &f);
		}
		if (dao_source_seek(s, 0, &err) < 0)
			abort();
	}
	dao_source_close(s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (path[0] == 0)
		setup();
	if (store(data, size) != 0)
		abort();
	read_raw();
	read_source();
	return 0;
}
