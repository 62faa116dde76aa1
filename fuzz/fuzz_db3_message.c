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

#include "harness.h"

#define MAX_PIXELS (1024u * 1024u)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char path[128], uri[160];
static const int codes[] = { -EINVAL, -EIO, -ENOMEM, -ENOENT, -EFBIG, 0 };

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
	sqlite3 *db;
	snprintf(path, sizeof(path), "%s/fuzz.db3", fuzz_temp_dir());
	snprintf(uri, sizeof(uri), "db3:%s", path);
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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (!path[0])
		setup();
	if (store(data, size) == 0)
		fuzz_play_source(uri, MAX_PIXELS, 2, codes);
	return 0;
}
