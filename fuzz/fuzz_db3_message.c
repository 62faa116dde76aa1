/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the message decode path of the "db3" source (rosbag2
 * sqlite3 bags; src/io/db3/db3_reader.c, src/io/plugin/ros2_source.c): what
 * a message's data blob holds, not SQLite's file format (libsqlite3's
 * business).  The input is: a byte choosing the depth topic's type (bit 0:
 * sensor_msgs/msg/CompressedImage, else Image), a little-endian u16 length
 * and that many bytes of the CameraInfo message, a u16 length and the first
 * depth message, and the second depth message (the rest).  A database laid
 * out as rosbag2 writes it is made with libsqlite3 once; each input's blobs
 * are written into it, then it is played as the built-in "db3" source with
 * a limit of 1024x1024 pixels (every frame, a seek back, every frame again).
 * Aborts on an error without a message or with an undocumented code.
 */
#include <errno.h>
#include <sqlite3.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <depthao/plugin.h>

#define MAX_PIXELS (1024u * 1024u)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char path[64], uri[80];
static struct dao_plugins *plugins;

static const char *const schema =
	"CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
	" serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
	"CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
	" timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
	"CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
	"INSERT INTO topics VALUES (1, '/camera/depth/camera_info', 'sensor_msgs/msg/CameraInfo',"
	" 'cdr', ''), (2, '/camera/depth/image_raw', 'sensor_msgs/msg/Image', 'cdr', '');"
	"INSERT INTO messages VALUES (1, 1, 1000, x''), (2, 2, 2000, x''), (3, 2, 3000, x'');";

static void setup(void)
{
	struct dao_error err;
	sqlite3 *db;
	if (dao_plugins_load(&plugins, "", &err) < 0)
		abort();
	snprintf(path, sizeof(path), "/tmp/fuzz-db3-%ld.db3", (long)getpid());
	snprintf(uri, sizeof(uri), "db3:%s", path);
	unlink(path);
	if (sqlite3_open(path, &db) != SQLITE_OK || sqlite3_exec(db, schema, NULL, NULL, NULL))
		abort();
	sqlite3_close(db);
}

/* The input's blobs into the database: 0, or -1 when the input is too short. */
static int store(const uint8_t *d, size_t n)
{
	const uint8_t *part[3];
	size_t len[3];
	if (n < 5)
		return -1;
	const char *type = d[0] & 1 ? "sensor_msgs/msg/CompressedImage" : "sensor_msgs/msg/Image";
	size_t at = 1;
	for (int k = 0; k < 2; k++) {
		if (at + 2 > n)
			return -1;
		len[k] = (size_t)d[at] | (size_t)d[at + 1] << 8;
		at += 2;
		if (len[k] > n - at)
			return -1;
		part[k] = d + at;
		at += len[k];
	}
	part[2] = d + at;
	len[2] = n - at;
	sqlite3 *db;
	sqlite3_stmt *st;
	if (sqlite3_open(path, &db) != SQLITE_OK)
		abort();
	if (sqlite3_prepare_v2(db, "UPDATE topics SET type = ?1 WHERE id = 2", -1, &st, NULL))
		abort();
	sqlite3_bind_text(st, 1, type, -1, SQLITE_STATIC);
	if (sqlite3_step(st) != SQLITE_DONE)
		abort();
	sqlite3_finalize(st);
	if (sqlite3_prepare_v2(db, "UPDATE messages SET data = ?1 WHERE id = ?2", -1, &st, NULL))
		abort();
	for (int k = 0; k < 3; k++) {
		sqlite3_reset(st);
		sqlite3_bind_blob(st, 1, part[k], (int)len[k], SQLITE_STATIC);
		sqlite3_bind_int(st, 2, k + 1);
		if (sqlite3_step(st) != SQLITE_DONE)
			abort();
	}
	sqlite3_finalize(st);
	sqlite3_close(db);
	return 0;
}

static void check_error(int ret, const struct dao_error *err)
{
	if (ret != -EINVAL && ret != -EIO && ret != -ENOMEM && ret != -ENOENT && ret != -EFBIG)
		abort();
	if (!err->message[0] || err->code != ret)
		abort();
}

static void play(void)
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
	if ((uint64_t)in.width * in.height > MAX_PIXELS || in.frame_count != 2)
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
		if (pass == 0 && dao_source_seek(s, 0, &err) < 0)
			abort();
	}
	dao_source_close(s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (!plugins)
		setup();
	if (store(data, size) == 0)
		play();
	return 0;
}
