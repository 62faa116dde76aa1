/* SPDX-License-Identifier: MIT */
/*
 * The MCAP reader on files built here record by record (mcap_format.h), the
 * hostile ones among them: a chunk claiming 4 GB, a zstd bomb, lengths past
 * the end, chunk indexes pointing elsewhere; CDR (both byte orders, the
 * alignment from the encapsulation's end, strings, sequences); the ROS 2
 * Image; compressedDepth's format strings and RVL.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zstd.h>

#include <cmocka.h>
#include <errno.h>

#include "mcap/cdr.h"
#include "mcap/foxglove_msg.h"
#include "mcap/compressed_depth.h"
#include "mcap/mcap_format.h"
#include "mcap/mcap_reader.h"
#include "mcap/ros2_msg.h"

/* A growing byte buffer: the file being built; the CDR written into it big-endian
 * (CDR_BE) when big_endian is set, little-endian (CDR_LE) otherwise. */
struct buf {
	uint8_t d[1 << 16];
	size_t n;
	int big_endian;
};

static void put(struct buf *b, const void *p, size_t n)
{
	assert_true(b->n + n <= sizeof b->d);
	memcpy(b->d + b->n, p, n);
	b->n += n;
}

static void put8(struct buf *b, uint8_t v) { put(b, &v, 1); }
static void put16(struct buf *b, uint16_t v) { uint8_t p[2]; dao_mcap_wr16(p, v); put(b, p, 2); }
static void put32(struct buf *b, uint32_t v) { uint8_t p[4]; dao_mcap_wr32(p, v); put(b, p, 4); }
static void put64(struct buf *b, uint64_t v) { uint8_t p[8]; dao_mcap_wr64(p, v); put(b, p, 8); }
static void putstr(struct buf *b, const char *s) { put32(b, (uint32_t)strlen(s)); put(b, s, strlen(s)); }

/* A record: opcode and length, its content in c. */
static void record(struct buf *b, uint8_t op, const struct buf *c)
{
	put8(b, op);
	put64(b, c->n);
	put(b, c->d, c->n);
}

static struct buf *content(void)
{
	static struct buf c;
	c.n = 0;
	return &c;
}

static void start(struct buf *b)
{
	b->n = 0;
	put(b, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN);
	struct buf *c = content();
	putstr(c, "ros2");
	putstr(c, "test");
	record(b, DAO_MCAP_OP_HEADER, c);
}

static void schema_and_channel(struct buf *b)
{
	struct buf *c = content();
	put16(c, 1);
	putstr(c, "sensor_msgs/msg/Image");
	putstr(c, "ros2msg");
	putstr(c, "uint32 x");
	record(b, DAO_MCAP_OP_SCHEMA, c);
	c = content();
	put16(c, 7);
	put16(c, 1);
	putstr(c, "/depth");
	putstr(c, "cdr");
	put32(c, 0);
	record(b, DAO_MCAP_OP_CHANNEL, c);
}

static void message(struct buf *b, uint16_t ch, uint64_t t, const char *data)
{
	struct buf *c = content();
	put16(c, ch);
	put32(c, 0);
	put64(c, t);
	put64(c, t);
	put(c, data, strlen(data));
	record(b, DAO_MCAP_OP_MESSAGE, c);
}

static char path[64];

static const char *store(const struct buf *b)
{
	snprintf(path, sizeof path, "/tmp/dao-mcap-test-%ld.mcap", (long)getpid());
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(b->d, 1, b->n, f), b->n);
	fclose(f);
	return path;
}

static int open_file(const struct buf *b, uint64_t max_chunk, struct dao_mcap **m,
		     struct dao_error *err)
{
	int r = dao_mcap_open(store(b), max_chunk, m, err);
	unlink(path);
	return r;
}

static void unchunked_in_time_order(void **state)
{
	(void)state;
	static struct buf b;
	start(&b);
	schema_and_channel(&b);
	message(&b, 7, 300, "c");
	message(&b, 7, 100, "a");
	message(&b, 7, 200, "b");
	struct buf *c = content();
	put32(c, 0);
	record(&b, DAO_MCAP_OP_DATA_END, c);
	struct dao_mcap *m;
	struct dao_error err;
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), 0);
	assert_int_equal(dao_mcap_topic_count(m), 1);
	const struct dao_mcap_topic *t = dao_mcap_topic(m, 0);
	assert_string_equal(t->name, "/depth");
	assert_string_equal(t->schema, "sensor_msgs/msg/Image");
	assert_string_equal(t->encoding, "cdr");
	assert_int_equal(t->message_count, 3);
	assert_null(dao_mcap_warning(m));
	assert_int_equal(dao_mcap_indexed(m), 0);
	for (uint32_t i = 0; i < 3; i++) {
		const uint8_t *d;
		uint64_t n, ts;
		assert_int_equal(dao_mcap_read_message(m, 0, i, &d, &n, &ts, &err), 0);
		assert_int_equal(n, 1);
		assert_int_equal(d[0], 'a' + i);
		assert_int_equal(ts, 100 * (i + 1));
	}
	assert_int_equal(dao_mcap_read_message(m, 0, 3, NULL, NULL, NULL, &err), -EINVAL);
	dao_mcap_close(m);
}

/* A data section whose CRC is given: right and wrong. */
static void data_end_crc(void **state)
{
	(void)state;
	static struct buf b;
	for (int wrong = 0; wrong < 2; wrong++) {
		start(&b);
		schema_and_channel(&b);
		message(&b, 7, 1, "x");
		uint32_t crc = dao_mcap_crc32(0, b.d, b.n);
		struct buf *c = content();
		put32(c, crc ^ (uint32_t)wrong);
		record(&b, DAO_MCAP_OP_DATA_END, c);
		struct dao_mcap *m = NULL;
		struct dao_error err;
		int r = open_file(&b, 1 << 20, &m, &err);
		if (wrong) {
			assert_int_equal(r, -EINVAL);
			assert_non_null(strstr(err.message, "data section's CRC does not match"));
		} else {
			assert_int_equal(r, 0);
			dao_mcap_close(m);
		}
	}
}

/* A chunk record around `records` (compression, claimed uncompressed size and CRC). */
static void chunk(struct buf *b, const char *comp, const void *records, size_t n,
		  uint64_t usize, uint32_t crc)
{
	static struct buf c;
	c.n = 0;
	put64(&c, 0);
	put64(&c, 0);
	put64(&c, usize);
	put32(&c, crc);
	putstr(&c, comp);
	put64(&c, n);
	put(&c, records, n);
	record(b, DAO_MCAP_OP_CHUNK, &c);
}

static void chunk_claiming_4gb(void **state)
{
	(void)state;
	static struct buf b, in;
	start(&b);
	in.n = 0;
	schema_and_channel(&in);
	chunk(&b, "", in.d, in.n, 4ull << 30, 0);
	struct dao_mcap *m;
	struct dao_error err;
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), -EFBIG);
	assert_non_null(strstr(err.message, "a chunk of 4294967296 bytes uncompressed, more than "
					    "the limit of 1048576"));
}

static void zstd_bomb(void **state)
{
	(void)state;
	static struct buf b;
	/* 64 MiB of zeros in a few KB, claimed as 1000 bytes and as 1 MiB */
	size_t big = 64u << 20;
	uint8_t *zeros = calloc(1, big);
	size_t cap = ZSTD_compressBound(big);
	uint8_t *z = malloc(cap);
	assert_non_null(zeros);
	assert_non_null(z);
	size_t zn = ZSTD_compress(z, cap, zeros, big, 3);
	assert_false(ZSTD_isError(zn));
	assert_true(zn < 16000);
	free(zeros);
	uint64_t claims[] = {1000, 1 << 20};
	for (int k = 0; k < 2; k++) {
		start(&b);
		chunk(&b, "zstd", z, zn, claims[k], 0);
		struct dao_mcap *m;
		struct dao_error err;
		int r = open_file(&b, 2 << 20, &m, &err);
		assert_int_equal(r, -EINVAL);
		assert_true(strstr(err.message, "does not decompress to its") ||
			    strstr(err.message, "larger than they can be"));
	}
	free(z);
}

static void unknown_compression_and_bad_crc(void **state)
{
	(void)state;
	static struct buf b, in;
	struct dao_mcap *m;
	struct dao_error err;
	in.n = 0;
	schema_and_channel(&in);
	message(&in, 7, 5, "m");
	start(&b);
	chunk(&b, "brotli", in.d, in.n, in.n, 0);
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), -EINVAL);
	assert_non_null(strstr(err.message, "a chunk compressed with 'brotli'"));
	start(&b);
	chunk(&b, "", in.d, in.n, in.n, dao_mcap_crc32(0, in.d, in.n) + 1);
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), -EINVAL);
	assert_non_null(strstr(err.message, "a chunk's CRC does not match"));
	start(&b);
	chunk(&b, "", in.d, in.n, in.n, dao_mcap_crc32(0, in.d, in.n));
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), 0);
	assert_int_equal(dao_mcap_topic(m, 0)->message_count, 1);
	dao_mcap_close(m);
}

/* Lengths past the end: a record inside a chunk, a record of the file (cut short). */
static void lengths_past_the_end(void **state)
{
	(void)state;
	static struct buf b, in;
	struct dao_mcap *m;
	struct dao_error err;
	in.n = 0;
	schema_and_channel(&in);
	message(&in, 7, 5, "m");
	dao_mcap_wr64(in.d + in.n - 31 + 1, 1000); /* the message's length */
	start(&b);
	chunk(&b, "", in.d, in.n, in.n, 0);
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), -EINVAL);
	assert_non_null(strstr(err.message, "a record in a chunk runs past the chunk's end"));
	start(&b);
	schema_and_channel(&b);
	message(&b, 7, 5, "first");
	message(&b, 7, 6, "second");
	b.n -= 3; /* cut short */
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), 0);
	assert_non_null(dao_mcap_warning(m));
	assert_non_null(strstr(dao_mcap_warning(m), "cut short"));
	assert_int_equal(dao_mcap_topic(m, 0)->message_count, 1);
	dao_mcap_close(m);
	/* a message of a channel nobody defined */
	start(&b);
	message(&b, 9, 5, "m");
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), -EINVAL);
	assert_non_null(strstr(err.message, "a message of channel 9, which no channel record defines"));
}

/* A summary whose chunk index points at the header instead of the chunk. */
static void chunk_index_elsewhere(void **state)
{
	(void)state;
	static struct buf b, in, s;
	in.n = 0;
	schema_and_channel(&in);
	message(&in, 7, 5, "m");
	start(&b);
	uint64_t chunk_pos = b.n;
	chunk(&b, "", in.d, in.n, in.n, 0);
	uint64_t chunk_len = b.n - chunk_pos;
	struct buf *c = content();
	put32(c, 0);
	record(&b, DAO_MCAP_OP_DATA_END, c);
	uint64_t summary = b.n;
	schema_and_channel(&b);
	s.n = 0;
	put64(&s, 0);
	put64(&s, 0);
	put64(&s, DAO_MCAP_MAGIC_LEN); /* the header, not the chunk */
	put64(&s, chunk_len);
	put32(&s, 0);                  /* no message indexes */
	put64(&s, 0);
	putstr(&s, "");
	put64(&s, in.n);
	put64(&s, in.n);
	record(&b, DAO_MCAP_OP_CHUNK_INDEX, &s);
	c = content();
	put64(c, summary);
	put64(c, 0);
	put32(c, 0);
	record(&b, DAO_MCAP_OP_FOOTER, c);
	put(&b, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN);
	struct dao_mcap *m;
	struct dao_error err;
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), -EINVAL);
	assert_non_null(strstr(err.message, "a chunk index points at no chunk of its size"));
	/* pointed right, the summary is used and the message read from the chunk */
	start(&b);
	chunk(&b, "", in.d, in.n, in.n, 0);
	c = content();
	put32(c, 0);
	record(&b, DAO_MCAP_OP_DATA_END, c);
	summary = b.n;
	schema_and_channel(&b);
	dao_mcap_wr64(s.d + 16, chunk_pos);
	record(&b, DAO_MCAP_OP_CHUNK_INDEX, &s);
	c = content();
	put64(c, summary);
	put64(c, 0);
	put32(c, 0);
	record(&b, DAO_MCAP_OP_FOOTER, c);
	put(&b, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN);
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), 0);
	assert_int_equal(dao_mcap_indexed(m), 1);
	const uint8_t *d;
	uint64_t n;
	assert_int_equal(dao_mcap_read_message(m, 0, 0, &d, &n, NULL, &err), 0);
	assert_int_equal(n, 1);
	assert_int_equal(d[0], 'm');
	dao_mcap_close(m);
}

static void not_mcap(void **state)
{
	(void)state;
	static struct buf b;
	struct dao_mcap *m;
	struct dao_error err;
	b.n = 0;
	put(&b, "#ROSBAG V2.0\nxxxxxxxxxxxxx", 26);
	assert_int_equal(open_file(&b, 1 << 20, &m, &err), -EINVAL);
	assert_non_null(strstr(err.message, "not an MCAP file"));
}

/* CDR: u8, then a u32 aligned to 4 and a f64 aligned to 8, counted after the 4-byte header. */
static void cdr_alignment_and_byte_order(void **state)
{
	(void)state;
	const uint8_t le[] = {0, 1, 0, 0, 0xAB, 0, 0, 0, 0x78, 0x56, 0x34, 0x12, 0xCD, 0, 0, 0,
			      0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xF0, 0x3F};
	const uint8_t be[] = {0, 0, 0, 0, 0xAB, 0, 0, 0, 0x12, 0x34, 0x56, 0x78, 0xCD, 0, 0, 0,
			      0, 0, 0, 0, 0x3F, 0xF0, 0, 0, 0, 0, 0, 0};
	const uint8_t *msgs[] = {le, be};
	for (int k = 0; k < 2; k++) {
		struct dao_cdr c;
		assert_int_equal(dao_cdr_init(&c, msgs[k], sizeof be), 0);
		assert_int_equal(dao_cdr_u8(&c), 0xAB);
		assert_int_equal(dao_cdr_u32(&c), 0x12345678);
		assert_int_equal(dao_cdr_u8(&c), 0xCD);
		assert_true(dao_cdr_f64(&c) == 1.0); /* at 16: 8-aligned after the header */
		assert_true(dao_cdr_ok(&c));
		assert_int_equal(dao_cdr_u8(&c), 0); /* past the end */
		assert_false(dao_cdr_ok(&c));
	}
	struct dao_cdr c;
	const uint8_t xcdr2[] = {0, 7, 0, 0, 1, 2, 3, 4};
	assert_int_equal(dao_cdr_init(&c, xcdr2, sizeof xcdr2), -ENOTSUP);
	assert_int_equal(dao_cdr_init(&c, xcdr2, 3), -EINVAL);
}

static void cdr_strings_and_sequences(void **state)
{
	(void)state;
	struct dao_cdr c;
	uint32_t n;
	const uint8_t ok[] = {0, 1, 0, 0, 3, 0, 0, 0, 'h', 'i', 0};
	assert_int_equal(dao_cdr_init(&c, ok, sizeof ok), 0);
	assert_string_equal(dao_cdr_string(&c, &n), "hi");
	assert_int_equal(n, 2);
	assert_true(dao_cdr_ok(&c));
	const uint8_t no_nul[] = {0, 1, 0, 0, 2, 0, 0, 0, 'h', 'i'};
	assert_int_equal(dao_cdr_init(&c, no_nul, sizeof no_nul), 0);
	dao_cdr_string(&c, &n);
	assert_false(dao_cdr_ok(&c));
	const uint8_t long_str[] = {0, 1, 0, 0, 0xff, 0xff, 0xff, 0xff, 'h', 0};
	assert_int_equal(dao_cdr_init(&c, long_str, sizeof long_str), 0);
	dao_cdr_string(&c, &n);
	assert_false(dao_cdr_ok(&c));
	const uint8_t seq[] = {0, 1, 0, 0, 0, 0, 0, 0x10, 1, 2};
	assert_int_equal(dao_cdr_init(&c, seq, sizeof seq), 0);
	assert_int_equal(dao_cdr_seq(&c, 1), 0);
	assert_false(dao_cdr_ok(&c));
}

/* What an image message parsed to, and the check of one stamped 5.000000007 s, 3x2. */
struct image_fields {
	uint64_t stamp_ns;
	uint32_t width, height;
	const char *encoding;
	uint32_t step;
	const uint8_t *data;
	size_t data_len;
};

static void image_is(const struct image_fields *got, const char *encoding, uint32_t step,
		     const char *data)
{
	assert_int_equal(got->stamp_ns, 5000000007ull);
	assert_int_equal(got->width, 3);
	assert_int_equal(got->height, 2);
	assert_string_equal(got->encoding, encoding);
	assert_int_equal(got->step, step);
	assert_int_equal(got->data_len, strlen(data));
	assert_memory_equal(got->data, data, strlen(data));
}

/* A ROS 2 Image: the fields as rosmsg2-serialization lays them out. */
static void ros2_image(void **state)
{
	(void)state;
	static struct buf b;
	b.n = 0;
	put(&b, "\0\1\0\0", 4);
	put32(&b, 5);          /* stamp.sec */
	put32(&b, 7);          /* stamp.nanosec */
	put32(&b, 2);          /* frame_id "f" */
	put(&b, "f\0", 2);
	put(&b, "\0\0", 2);    /* to 4 */
	put32(&b, 2);          /* height */
	put32(&b, 3);          /* width */
	put32(&b, 6);
	put(&b, "16UC1\0", 6);
	put8(&b, 0);           /* is_bigendian */
	put8(&b, 0);           /* to 4 */
	put32(&b, 6);          /* step */
	put32(&b, 12);
	put(&b, "abcdefghijkl", 12);
	struct dao_ros2_image img;
	assert_int_equal(dao_ros2_image_parse(b.d, b.n, &img), 0);
	image_is(&(struct image_fields){ img.header.stamp_ns, img.width, img.height, img.encoding,
					 img.step, img.data, img.data_len },
		 "16UC1", 6, "abcdefghijkl");
	for (size_t cut = 0; cut < b.n; cut++)
		assert_int_equal(dao_ros2_image_parse(b.d, cut, &img), -EINVAL);
}

/* CDR built by hand in the buffer's byte order: padding to an alignment counted after
 * the encapsulation header, a u32 or u64 (aligned to its size), a string (its NUL
 * counted), a float64. */
static void cdr_pad(struct buf *b, size_t align)
{
	while ((b->n - 4) % align)
		put8(b, 0);
}

static void cdr_uint(struct buf *b, uint64_t v, size_t n)
{
	cdr_pad(b, n);
	for (size_t i = 0; i < n; i++)
		put8(b, (uint8_t)(v >> 8 * (b->big_endian ? n - 1 - i : i)));
}

static void cdr_u32(struct buf *b, uint32_t v)
{
	cdr_uint(b, v, 4);
}

static void cdr_str(struct buf *b, const char *s, size_t n)
{
	cdr_u32(b, (uint32_t)n + 1);
	put(b, s, n);
	put8(b, 0);
}

static void cdr_f64(struct buf *b, double v)
{
	uint64_t u;
	memcpy(&u, &v, 8);
	cdr_uint(b, u, 8);
}

/* The encapsulation (CDR_BE 0x00 0x00 or CDR_LE 0x00 0x01, two option bytes), a
 * builtin_interfaces/Time and a frame_id: the start of each of Foxglove's ROS 2 messages. */
static void fg_cdr_start(struct buf *b, int32_t sec, uint32_t nsec, const char *frame,
			 size_t frame_len)
{
	b->n = 0;
	put(b, b->big_endian ? "\0\0\0\0" : "\0\1\0\0", 4);
	cdr_u32(b, (uint32_t)sec);
	cdr_u32(b, nsec);
	cdr_str(b, frame, frame_len);
}

/* foxglove_msgs/msg/RawImage: timestamp, frame_id, width, height, encoding, step, data. */
static size_t fg_cdr_raw(struct buf *b, int32_t sec, uint32_t nsec, const char *frame,
			 size_t frame_len)
{
	fg_cdr_start(b, sec, nsec, frame, frame_len);
	cdr_u32(b, 3);         /* width */
	cdr_u32(b, 2);         /* height */
	cdr_str(b, "32FC1", 5);
	cdr_u32(b, 12);        /* step */
	cdr_u32(b, 24);
	put(b, "abcdefghijklmnopqrstuvwx", 24);
	return b->n;
}

static void fg_cdr_raw_image(void **state)
{
	(void)state;
	static struct buf b;
	struct dao_fg_image img;
	size_t n = fg_cdr_raw(&b, 5, 7, "cam", 3);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, n, NULL, &img), 0);
	assert_string_equal(img.frame_id, "cam");
	image_is(&(struct image_fields){ img.stamp_ns, img.width, img.height, img.encoding, img.step,
					 img.data, img.data_len },
		 "32FC1", 12, "abcdefghijklmnopqrstuvwx");
	for (size_t cut = 0; cut < n; cut++)
		assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, cut, NULL, &img), -EINVAL);
	/* as protobuf and JSON: a stamp before 1970 is 0, a nanosecond count of 1e9 refused */
	fg_cdr_raw(&b, -3, 7, "cam", 3);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), 0);
	assert_int_equal(img.stamp_ns, 0);
	fg_cdr_raw(&b, 5, 1000000000u, "cam", 3);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), -EINVAL);
	/* a frame_id holding a NUL, or of 256 bytes, refused; of 255 taken */
	fg_cdr_raw(&b, 5, 7, "ca\0m", 4);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), -EINVAL);
	char frame[257];
	memset(frame, 'f', 256);
	frame[256] = 0;
	fg_cdr_raw(&b, 5, 7, frame, 256);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), -EINVAL);
	fg_cdr_raw(&b, 5, 7, frame, 255);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), 0);
	assert_int_equal(strlen(img.frame_id), 255);
	/* another encapsulation (XCDR2) */
	b.d[1] = 7;
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), -ENOTSUP);
}

/* foxglove_msgs/msg/CompressedImage: timestamp, frame_id, data, format (after the data). */
static size_t fg_cdr_compressed(struct buf *b)
{
	fg_cdr_start(b, 9, 0, "", 0);
	cdr_u32(b, 5);
	put(b, "\x89PNG!", 5);
	cdr_str(b, "png", 3);
	return b->n;
}

static void fg_cdr_compressed_image(void **state)
{
	(void)state;
	static struct buf b;
	struct dao_fg_image img;
	fg_cdr_compressed(&b);
	assert_int_equal(dao_fg_compressed_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), 0);
	assert_int_equal(img.stamp_ns, 9000000000ull);
	assert_string_equal(img.frame_id, "");
	assert_string_equal(img.encoding, "png");
	assert_int_equal(img.data_len, 5);
	assert_memory_equal(img.data, "\x89PNG!", 5);
	for (size_t cut = 0; cut < b.n; cut++)
		assert_int_equal(dao_fg_compressed_image_parse(DAO_FG_CDR, b.d, cut, NULL, &img),
				 -EINVAL);
	/* a format of 64 bytes does not fit */
	char fmt[65];
	memset(fmt, 'j', 64);
	b.n -= 8;
	cdr_str(&b, fmt, 64);
	assert_int_equal(dao_fg_compressed_image_parse(DAO_FG_CDR, b.d, b.n, NULL, &img), -EINVAL);
}

/* foxglove_msgs/msg/CameraCalibration: timestamp, frame_id, width, height,
 * distortion_model, d (float64[]), k[9], r[9], p[12]. */
static size_t fg_cdr_calibration(struct buf *b, uint32_t nd)
{
	fg_cdr_start(b, 1, 2, "cam", 3);
	cdr_u32(b, 64);
	cdr_u32(b, 48);
	cdr_str(b, "plumb_bob", 9);
	cdr_u32(b, nd);
	for (uint32_t i = 0; i < nd; i++)
		cdr_f64(b, 0.5 + i);
	for (int i = 0; i < 30; i++)
		cdr_f64(b, 100.0 + i);
	return b->n;
}

static void fg_cdr_camera_calibration(void **state)
{
	(void)state;
	static struct buf b;
	struct dao_fg_calibration c;
	size_t n = fg_cdr_calibration(&b, 5);
	assert_int_equal(dao_fg_calibration_parse(DAO_FG_CDR, b.d, n, &c), 0);
	assert_int_equal(c.stamp_ns, 1000000002ull);
	assert_int_equal(c.width, 64);
	assert_int_equal(c.height, 48);
	assert_int_equal(c.d_count, 5);
	assert_true(c.d[4] == 4.5);
	assert_true(c.k[0] == 100.0 && c.k[8] == 108.0);
	assert_true(c.r[0] == 109.0 && c.p[0] == 118.0 && c.p[11] == 129.0);
	for (size_t cut = 0; cut < n; cut++)
		assert_int_equal(dao_fg_calibration_parse(DAO_FG_CDR, b.d, cut, &c), -EINVAL);
	/* more distortion values than kept: counted, the first 16 kept */
	n = fg_cdr_calibration(&b, 20);
	assert_int_equal(dao_fg_calibration_parse(DAO_FG_CDR, b.d, n, &c), 0);
	assert_int_equal(c.d_count, 20);
	assert_true(c.d[15] == 15.5 && c.k[0] == 100.0);
	/* a count of D larger than the message */
	n = fg_cdr_calibration(&b, 5);
	b.d[4 + 40] = 0xff; /* its low byte, after "plumb_bob" and the padding to 4 */
	assert_int_equal(dao_fg_calibration_parse(DAO_FG_CDR, b.d, n, &c), -EINVAL);
}

/* Two images read from messages: the same fields, the same data bytes. */
static void fg_images_equal(const struct dao_fg_image *a, const struct dao_fg_image *b)
{
	assert_int_equal(a->stamp_ns, b->stamp_ns);
	assert_string_equal(a->frame_id, b->frame_id);
	assert_int_equal(a->width, b->width);
	assert_int_equal(a->height, b->height);
	assert_int_equal(a->step, b->step);
	assert_string_equal(a->encoding, b->encoding);
	assert_int_equal(a->data_len, b->data_len);
	assert_memory_equal(a->data, b->data, a->data_len);
}

/*
 * Foxglove's RawImage, CompressedImage and CameraCalibration in big-endian CDR (CDR_BE,
 * 0x00 0x00): read as the same messages in little-endian are, each number in the
 * message's byte order, a uint8[]'s bytes (the pixels) as they are; cut short at any
 * byte refused. The same bytes under a CDR_LE header are refused (frame_id's length read
 * the other way round runs past the end), so the header's byte order is the one used.
 */
static void fg_cdr_big_endian(void **state)
{
	(void)state;
	static struct buf le, be;
	be.big_endian = 1;
	struct dao_fg_image li, bi;
	fg_cdr_raw(&le, 5, 7, "cam", 3);
	fg_cdr_raw(&be, 5, 7, "cam", 3);
	assert_int_equal(be.n, le.n);
	/* written big-endian: the header, and the width after the Time and "cam" */
	assert_memory_equal(be.d, "\0\0\0\0", 4);
	assert_memory_equal(be.d + 4 + 16, "\0\0\0\3", 4);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, le.d, le.n, NULL, &li), 0);
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, be.d, be.n, NULL, &bi), 0);
	fg_images_equal(&bi, &li);
	assert_string_equal(bi.frame_id, "cam");
	image_is(&(struct image_fields){ bi.stamp_ns, bi.width, bi.height, bi.encoding, bi.step,
					 bi.data, bi.data_len },
		 "32FC1", 12, "abcdefghijklmnopqrstuvwx");
	for (size_t cut = 0; cut < be.n; cut++)
		assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, be.d, cut, NULL, &bi), -EINVAL);
	be.d[1] = 1;
	assert_int_equal(dao_fg_raw_image_parse(DAO_FG_CDR, be.d, be.n, NULL, &bi), -EINVAL);

	fg_cdr_compressed(&le);
	fg_cdr_compressed(&be);
	assert_int_equal(dao_fg_compressed_image_parse(DAO_FG_CDR, le.d, le.n, NULL, &li), 0);
	assert_int_equal(dao_fg_compressed_image_parse(DAO_FG_CDR, be.d, be.n, NULL, &bi), 0);
	fg_images_equal(&bi, &li);
	assert_int_equal(bi.stamp_ns, 9000000000ull);
	assert_string_equal(bi.encoding, "png");
	assert_memory_equal(bi.data, "\x89PNG!", 5);
	for (size_t cut = 0; cut < be.n; cut++)
		assert_int_equal(dao_fg_compressed_image_parse(DAO_FG_CDR, be.d, cut, NULL, &bi),
				 -EINVAL);

	/* D's float64s 8-aligned after a count that ends 4 bytes past a multiple of 8 */
	struct dao_fg_calibration lc, bc;
	fg_cdr_calibration(&le, 5);
	fg_cdr_calibration(&be, 5);
	assert_int_equal(dao_fg_calibration_parse(DAO_FG_CDR, le.d, le.n, &lc), 0);
	assert_int_equal(dao_fg_calibration_parse(DAO_FG_CDR, be.d, be.n, &bc), 0);
	assert_int_equal(bc.stamp_ns, lc.stamp_ns);
	assert_int_equal(bc.width, lc.width);
	assert_int_equal(bc.height, lc.height);
	assert_int_equal(bc.d_count, lc.d_count);
	for (int i = 0; i < DAO_FG_MAX_DISTORTION; i++)
		assert_true(bc.d[i] == lc.d[i]);
	for (int i = 0; i < 9; i++)
		assert_true(bc.k[i] == lc.k[i] && bc.r[i] == lc.r[i]);
	for (int i = 0; i < 12; i++)
		assert_true(bc.p[i] == lc.p[i]);
	assert_true(bc.stamp_ns == 1000000002ull && bc.width == 64 && bc.d_count == 5);
	assert_true(bc.d[4] == 4.5 && bc.k[0] == 100.0 && bc.p[11] == 129.0);
	for (size_t cut = 0; cut < be.n; cut++)
		assert_int_equal(dao_fg_calibration_parse(DAO_FG_CDR, be.d, cut, &bc), -EINVAL);
}

static void compressed_depth_formats(void **state)
{
	(void)state;
	struct dao_cdepth_format f;
	assert_int_equal(dao_cdepth_parse_format("16UC1; compressedDepth png", &f), 0);
	assert_int_equal(f.codec, DAO_CDEPTH_PNG);
	assert_int_equal(f.is_float, 0);
	assert_int_equal(dao_cdepth_parse_format("16UC1; compressedDepth", &f), 0);
	assert_int_equal(f.codec, DAO_CDEPTH_PNG);
	assert_int_equal(dao_cdepth_parse_format("32FC1; compressedDepth rvl", &f), 0);
	assert_int_equal(f.codec, DAO_CDEPTH_RVL);
	assert_int_equal(f.is_float, 1);
	assert_int_equal(dao_cdepth_parse_format("rgb8; jpeg compressed bgr8", &f), -EINVAL);
	assert_int_equal(dao_cdepth_parse_format("16UC1; compressedDepth tiff", &f), -EINVAL);
	assert_int_equal(dao_cdepth_parse_format("jpeg", &f), -EINVAL);
}

/*
 * RVL of {0, 0, 5, 6}: zeros 2, non-zeros 2, zig-zag deltas 10 and 2, as nibbles
 * (3 bits each, least significant first, 8 = more): 2 | 2 | 10 -> 0xA 0x1 | 2, in one
 * word from its top nibble: 0x22A12000.
 */
static void rvl_decode(void **state)
{
	(void)state;
	const uint8_t in[] = {0x00, 0x20, 0xA1, 0x22};
	uint16_t out[4];
	assert_int_equal(dao_rvl_decode(in, sizeof in, out, 4), 0);
	assert_int_equal(out[0], 0);
	assert_int_equal(out[1], 0);
	assert_int_equal(out[2], 5);
	assert_int_equal(out[3], 6);
	assert_int_equal(dao_rvl_decode(in, sizeof in, out, 5), -EINVAL);
	assert_int_equal(dao_rvl_decode(in, 3, out, 4), -EINVAL);
	/* a run longer than the image */
	const uint8_t run[] = {0x00, 0x00, 0x00, 0x7F};
	assert_int_equal(dao_rvl_decode(run, sizeof run, out, 4), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(unchunked_in_time_order),
		cmocka_unit_test(data_end_crc),
		cmocka_unit_test(chunk_claiming_4gb),
		cmocka_unit_test(zstd_bomb),
		cmocka_unit_test(unknown_compression_and_bad_crc),
		cmocka_unit_test(lengths_past_the_end),
		cmocka_unit_test(chunk_index_elsewhere),
		cmocka_unit_test(not_mcap),
		cmocka_unit_test(cdr_alignment_and_byte_order),
		cmocka_unit_test(cdr_strings_and_sequences),
		cmocka_unit_test(ros2_image),
		cmocka_unit_test(fg_cdr_raw_image),
		cmocka_unit_test(fg_cdr_compressed_image),
		cmocka_unit_test(fg_cdr_camera_calibration),
		cmocka_unit_test(fg_cdr_big_endian),
		cmocka_unit_test(compressed_depth_formats),
		cmocka_unit_test(rvl_decode),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
