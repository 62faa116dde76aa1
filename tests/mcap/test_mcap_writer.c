/* SPDX-License-Identifier: MIT */
/*
 * The MCAP writer (mcap_writer.c) read back by depthao's reader: every
 * compression, through the summary's indexes; the file cut at every byte
 * of its data section reads a prefix of the messages, complete chunks
 * only, never an error past the first chunk; the ROS 2 encoders decode
 * with the CDR reader (ros2_msg.c); misuse is refused.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>
#include <errno.h>

#include "mcap/mcap_reader.h"
#include "mcap/mcap_writer.h"
#include "mcap/ros2_encode.h"
#include "mcap/ros2_msg.h"

#define NMSG 60

static char dir[] = "/tmp/dao-mcapw.XXXXXX";

static void payload(uint8_t *p, size_t n, unsigned i)
{
	for (size_t k = 0; k < n; k++)
		p[k] = (uint8_t)(i * 31 + k * 7);
}

static size_t msg_len(unsigned i)
{
	return 10 + (i * 37) % 300;
}

/* NMSG messages on two channels (even: 0, odd: 1), log time 1000 * (i + 1). */
static void write_file(const char *path, enum dao_mcap_compression c, uint64_t chunk)
{
	struct dao_error err;
	struct dao_mcap_writer *w;
	struct dao_mcap_writer_options o = {.compression = c, .chunk_size = chunk, .profile = "ros2"};
	uint16_t s, ch0, ch1;
	assert_int_equal(dao_mcap_writer_open(path, &o, &w, &err), 0);
	assert_int_equal(dao_mcap_writer_add_schema(w, "sensor_msgs/msg/Image", "ros2msg",
						    dao_ros2_image_schema, &s, &err), 0);
	assert_int_equal(dao_mcap_writer_add_channel(w, s, "/a", "cdr", &ch0, &err), 0);
	assert_int_equal(dao_mcap_writer_add_channel(w, s, "/b", "cdr", &ch1, &err), 0);
	for (unsigned i = 0; i < NMSG; i++) {
		uint8_t *p;
		uint64_t t = 1000 * (uint64_t)(i + 1);
		assert_int_equal(dao_mcap_writer_message(w, i % 2 ? ch1 : ch0, t, t, msg_len(i), &p,
							 &err), 0);
		payload(p, msg_len(i), i);
	}
	/* a schema after the first message is refused */
	assert_int_equal(dao_mcap_writer_add_schema(w, "x", "ros2msg", "", &s, &err), -EINVAL);
	assert_int_equal(dao_mcap_writer_message(w, 7, 0, 0, 1, &(uint8_t *){NULL}, &err), -EINVAL);
	assert_int_equal(dao_mcap_writer_finish(w, &err), 0);
}

/* The messages the reader gives: all NMSG in order when `full`, else a prefix; returns
 * how many (both topics). */
static unsigned read_back(const char *path, int full)
{
	struct dao_error err;
	struct dao_mcap *m;
	int r = dao_mcap_open(path, 1 << 24, &m, &err);
	if (!full && r == -EINVAL)
		return 0; /* not one complete chunk yet */
	assert_int_equal(r, 0);
	if (full)
		assert_true(dao_mcap_indexed(m));
	unsigned n = 0;
	for (int t = 0; t < 2; t++) {
		int k = dao_mcap_find_topic(m, t ? "/b" : "/a");
		if (k < 0) {
			assert_false(full);
			continue;
		}
		const struct dao_mcap_topic *tp = dao_mcap_topic(m, (uint32_t)k);
		assert_string_equal(tp->schema, "sensor_msgs/msg/Image");
		for (uint32_t j = 0; j < tp->message_count; j++) {
			const uint8_t *d;
			uint64_t len, t0;
			unsigned i = 2 * j + (unsigned)t;
			uint8_t want[400];
			assert_int_equal(dao_mcap_read_message(m, (uint32_t)k, j, &d, &len, &t0, &err), 0);
			payload(want, msg_len(i), i);
			assert_int_equal(len, msg_len(i));
			assert_memory_equal(d, want, len);
			assert_int_equal(t0, 1000 * (uint64_t)(i + 1));
			n++;
		}
	}
	dao_mcap_close(m);
	return n;
}

static void every_compression(void **state)
{
	(void)state;
	char path[64];
	for (int c = 0; c <= DAO_MCAP_COMPRESS_NONE; c++) {
		snprintf(path, sizeof path, "%s/c%d.mcap", dir, c);
		write_file(path, (enum dao_mcap_compression)c, 1000);
		assert_int_equal(read_back(path, 1), NMSG);
	}
}

/* Cut at every byte: each prefix reads a prefix of the messages, growing with the cut. */
static void cut_anywhere(void **state)
{
	(void)state;
	char path[64], cut[64];
	snprintf(path, sizeof path, "%s/full.mcap", dir);
	snprintf(cut, sizeof cut, "%s/cut.mcap", dir);
	write_file(path, DAO_MCAP_COMPRESS_ZSTD, 700);
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	static uint8_t buf[1 << 16];
	size_t size = fread(buf, 1, sizeof buf, f);
	fclose(f);
	assert_true(size > 0 && size < sizeof buf);
	unsigned last = 0, chunks_seen = 0;
	for (size_t n = 8; n <= size; n++) {
		FILE *o = fopen(cut, "wb");
		assert_non_null(o);
		assert_int_equal(fwrite(buf, 1, n, o), n);
		fclose(o);
		unsigned got = read_back(cut, n == size);
		/* whole chunks: both topics' messages of a chunk at once, never fewer than before */
		assert_true(got >= last);
		chunks_seen += got > last;
		last = got;
	}
	assert_int_equal(last, NMSG);
	assert_true(chunks_seen >= 5); /* the messages came chunk by chunk */
}

static void encoders_decode(void **state)
{
	(void)state;
	uint16_t px[6] = {1, 2, 3, 65535, 5, 6};
	struct dao_frame f = {.format = DAO_PIXFMT_GRAY16, .width = 3, .height = 2, .stride = 6,
			      .data = px};
	uint8_t msg[512];
	size_t n = dao_ros2_image_size("cam", "mono16", &f);
	assert_true(n <= sizeof msg);
	dao_ros2_image_encode(msg, 1234567890123ull, "cam", "mono16", &f);
	struct dao_ros2_image img;
	assert_int_equal(dao_ros2_image_parse(msg, n, &img), 0);
	assert_int_equal(img.header.stamp_ns, 1234567890123ull);
	assert_int_equal(img.width, 3);
	assert_int_equal(img.height, 2);
	assert_int_equal(img.step, 6);
	assert_string_equal(img.encoding, "mono16");
	assert_int_equal(img.data_len, 12);
	assert_memory_equal(img.data, px, 12);
	struct dao_ros2_pinhole k = {640, 480, 525, 526, 319.5, 239.5};
	n = dao_ros2_camera_info_size("cam");
	assert_true(n <= sizeof msg);
	dao_ros2_camera_info_encode(msg, 5, "cam", &k);
	struct dao_ros2_camera_info ci;
	assert_int_equal(dao_ros2_camera_info_parse(msg, n, &ci), 0);
	assert_int_equal(ci.width, 640);
	assert_true(ci.k[0] == 525 && ci.k[2] == 319.5 && ci.k[4] == 526 && ci.k[5] == 239.5);
	assert_true(ci.p[0] == 525 && ci.p[10] == 1 && ci.r[0] == 1 && ci.r[4] == 1);
	assert_int_equal(ci.distortion_count, 5);
	assert_string_equal(ci.distortion_model, "plumb_bob");
}

static void misuse(void **state)
{
	(void)state;
	struct dao_error err;
	struct dao_mcap_writer *w;
	struct dao_mcap_writer_options o = {0};
	char path[64];
	struct stat st;
	snprintf(path, sizeof path, "%s/full.mcap", dir);
	assert_int_equal(dao_mcap_writer_open(path, &o, &w, &err), -EEXIST);
	assert_non_null(strstr(err.message, "never replaces"));
	assert_int_equal(dao_mcap_writer_open(dir, &o, &w, &err), -EISDIR);
	snprintf(path, sizeof path, "%s/gone.mcap", dir);
	assert_int_equal(dao_mcap_writer_open(path, &o, &w, &err), 0);
	dao_mcap_writer_abort(w); /* nothing recorded: no file */
	assert_int_not_equal(stat(path, &st), 0);
	o.compression = (enum dao_mcap_compression)7;
	assert_int_equal(dao_mcap_writer_open(path, &o, &w, &err), -EINVAL);
}

static int teardown(void **state)
{
	(void)state;
	char cmd[64];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
	if (!mkdtemp(dir))
		return 1;
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(every_compression),
		cmocka_unit_test(cut_anywhere),
		cmocka_unit_test(encoders_decode),
		cmocka_unit_test(misuse),
	};
	return cmocka_run_group_tests(tests, NULL, teardown);
}
