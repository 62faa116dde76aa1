/* SPDX-License-Identifier: MIT */
/*
 * Built-in source "db3": depth images from a rosbag2 bag in its sqlite3
 * storage (db3/db3_reader.c).  URI: FILE.db3 or DIR (a rosbag2 directory:
 * its metadata.yaml names the storage and the file; a directory of MCAP
 * storage is played by the mcap source), [?topic=T][&unit=M][&color=C] (the
 * options in any order).  The messages, the topic choice, the unit, the
 * intrinsics and the colour pairing are ros2_source.c's: topics.type is the
 * schema, topics.serialization_format the message encoding ("cdr"), a
 * message's timestamp its log time.
 */
#include <depthao/plugin.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "core/error_internal.h"
#include "db3/db3_reader.h"
#include "plugin/builtin.h"
#include "plugin/ros2_source.h"
#include "plugin/ros_image.h"

static int is_bag_dir(const char *path, size_t n)
{
	char name[4096];
	struct stat st;
	if (n + sizeof "/metadata.yaml" > sizeof name)
		return 0;
	snprintf(name, sizeof name, "%.*s/metadata.yaml", (int)n, path);
	return stat(name, &st) == 0 && S_ISREG(st.st_mode);
}

static int db3_probe(const char *uri)
{
	size_t n = dao_uri_path_len(uri, dao_ros_uri_options);
	if (n > 4 && !strncasecmp(uri + n - 4, ".db3", 4))
		return 60;
	return is_bag_dir(uri, n) ? 60 : 0;
}

static const char *store_path(const void *db)
{
	return dao_db3_path(db);
}

static const char *store_warning(const void *db)
{
	(void)db;
	return NULL;
}

static uint32_t store_topic_count(const void *db)
{
	return dao_db3_topic_count(db);
}

static void store_topic(const void *db, uint32_t i, struct dao_ros2_topic *t)
{
	const struct dao_db3_topic *dt = dao_db3_topic(db, i);
	t->name = dt->name;
	t->schema = dt->type;
	t->encoding = dt->serialization_format;
	t->message_count = dt->message_count;
}

static int store_read(void *db, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		      uint64_t *log_time, struct dao_error *err)
{
	return dao_db3_read_message(db, topic, i, data, len, log_time, err);
}

static uint64_t store_time(const void *db, uint32_t topic, uint32_t i)
{
	return dao_db3_message_time(db, topic, i);
}

static void store_close(void *db)
{
	dao_db3_close(db);
}

static const struct dao_ros2_store_ops db3_store = {
	.path = store_path,
	.warning = store_warning,
	.topic_count = store_topic_count,
	.topic = store_topic,
	.read_message = store_read,
	.message_time = store_time,
	.close = store_close,
};

/* A rosbag2 directory: u->path becomes its database file; *is_mcap for MCAP storage. */
static int resolve_dir(struct dao_ros_uri *u, int *is_mcap, struct dao_error *err)
{
	char storage[64], file[4096];
	int r = dao_rosbag2_metadata(u->path, storage, sizeof storage, file, sizeof file, err);
	if (r < 0)
		return r;
	if (strcmp(storage, "sqlite3") && strcmp(storage, "mcap"))
		return dao_error_set(err, -ENOTSUP, "%s/metadata.yaml: storage '%s': depthao reads "
				     "sqlite3 and mcap", u->path, storage);
	*is_mcap = !strcmp(storage, "mcap");
	char *p = strdup(file);
	if (!p)
		return dao_error_set(err, -ENOMEM, "out of memory");
	free(u->path);
	u->path = p;
	return 0;
}

int dao_db3_source_open(const char *uri, const struct dao_source_options *opts,
			uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct dao_ros_uri u;
	struct stat st;
	struct dao_db3 *db;
	int is_mcap = 0;
	int r = dao_ros_uri_parse(uri, "db3", &u, err);
	if (r == 0 && stat(u.path, &st) == 0 && S_ISDIR(st.st_mode))
		r = resolve_dir(&u, &is_mcap, err);
	if (r == 0 && is_mcap)
		r = dao_mcap_source_open_path(&u, opts, max_pixels, state, err);
	/* a message holds one image (up to 4 bytes a pixel) and its header */
	else if (r == 0 && (r = dao_db3_open(u.path, 4 * max_pixels + (1u << 20), &db, err)) == 0)
		r = dao_ros2_source_open(&db3_store, db, &u, "db3", opts, max_pixels, state, err);
	dao_ros_uri_free(&u);
	return r;
}

static int db3_open(const char *uri, const struct dao_source_options *opts, void **state,
		    struct dao_error *err)
{
	return dao_db3_source_open(uri, opts, DAO_DEFAULT_MAX_PIXELS, state, err);
}

static const struct dao_source_ops db3_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = db3_probe,
	.open = db3_open,
	.get_info = dao_ros2_source_get_info,
	.start = dao_ros2_source_start,
	.read = dao_ros2_source_read,
	.seek = dao_ros2_source_seek,
	.close = dao_ros2_source_close,
};

const struct dao_plugin dao_builtin_db3_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "db3",
	.description = "rosbag2 sqlite3 bags (.db3, or a bag directory with metadata.yaml): the "
		       "mcap source's messages (CDR Image, compressedDepth, CameraInfo, colour; "
		       "Foxglove schemas); FILE.db3|DIR[?topic=T][&unit=M][&color=C]",
	.source = &db3_source_ops,
};
