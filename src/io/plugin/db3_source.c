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
#include <unistd.h>

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

static const char *store_warning(const void *m)
{
	(void)m;
	return NULL;
}

static const char *multi_path(const void *m)
{
	return dao_db3_multi_path(m);
}

static uint32_t multi_topic_count(const void *m)
{
	return dao_db3_multi_topic_count(m);
}

static void multi_topic(const void *m, uint32_t i, struct dao_ros2_topic *t)
{
	const struct dao_db3_topic *dt = dao_db3_multi_topic(m, i);
	t->name = dt->name;
	t->schema = dt->type;
	t->encoding = dt->serialization_format;
	t->schema_encoding = ""; /* rosbag2's sqlite3 storage has none */
	t->message_count = dt->message_count;
}

static int multi_read(void *m, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		      uint64_t *log_time, struct dao_error *err)
{
	return dao_db3_multi_read_message(m, topic, i, data, len, log_time, err);
}

static uint64_t multi_time(const void *m, uint32_t topic, uint32_t i)
{
	return dao_db3_multi_message_time(m, topic, i);
}

static void multi_close(void *m)
{
	dao_db3_multi_close(m);
}

/* A bag's files played in their order as one (db3/db3_multi.c); a lone .db3 is a
 * bag of one file. */
static const struct dao_ros2_store_ops db3_multi_store = {
	.path = multi_path,
	.warning = store_warning,
	.topic_count = multi_topic_count,
	.topic = multi_topic,
	.read_message = multi_read,
	.message_time = multi_time,
	.close = multi_close,
};

/* rosbag2's compression_mode: 'f' (file), 'm' (message), 0 (none or another). */
static int compression_mode(const struct dao_rosbag2_meta *m)
{
	if (!m->compression_format[0])
		return 0;
	if (!strcasecmp(m->compression_mode, "file"))
		return 'f';
	return !strcasecmp(m->compression_mode, "message") ? 'm' : 0;
}

/* One file of a bag; a whole-file zstd one decompressed into a temporary file first. */
static int open_one(const char *file, int zstd_file, uint64_t max_message, struct dao_db3 **db,
		    struct dao_error *err)
{
	char tmp[4096];
	if (!zstd_file)
		return dao_db3_open(file, max_message, db, err);
	int r = dao_db3_unzstd_file(file, tmp, sizeof tmp, err);
	if (r < 0)
		return r;
	r = dao_db3_open(tmp, max_message, db, err);
	unlink(tmp); /* sqlite keeps it open: it goes when the bag is closed */
	return r;
}

/* What of a rosbag2 directory's metadata depthao does not play: 0, or -ENOTSUP said. */
static int check_meta(const char *dir, const struct dao_rosbag2_meta *m, struct dao_error *err)
{
	if (strcmp(m->storage, "sqlite3") && strcmp(m->storage, "mcap"))
		return dao_error_set(err, -ENOTSUP, "%s/metadata.yaml: storage '%s': depthao reads "
				     "sqlite3 and mcap", dir, m->storage);
	if (m->compression_format[0] &&
	    (strcmp(m->compression_format, "zstd") || !compression_mode(m)))
		return dao_error_set(err, -ENOTSUP, "%s/metadata.yaml: compression_format '%s' "
				     "(mode '%s'): depthao reads rosbag2's zstd, in file or "
				     "message mode; decompress the bag first",
				     dir, m->compression_format, m->compression_mode);
	if (m->compression_format[0] && !strcmp(m->storage, "mcap"))
		return dao_error_set(err, -ENOTSUP, "%s/metadata.yaml: an MCAP bag compressed by "
				     "rosbag2: decompress the bag first (MCAP's own chunk "
				     "compression is read)", dir);
	if (!strcmp(m->storage, "mcap") && m->file_count > 1)
		return dao_error_set(err, -ENOTSUP, "%s/metadata.yaml: an MCAP bag split into %u "
				     "files: play each file on its own", dir, m->file_count);
	return 0;
}

/* The .db3 files of a rosbag2 directory's metadata, as one store. */
static int open_split(const char *dir, const struct dao_rosbag2_meta *m, uint64_t max_message,
		      struct dao_db3_multi **out, struct dao_error *err)
{
	struct dao_db3 **dbs = calloc(m->file_count, sizeof *dbs);
	if (!dbs)
		return dao_error_set(err, -ENOMEM, "out of memory");
	int r = 0;
	uint32_t n = 0;
	for (; n < m->file_count && r == 0; n++)
		if ((r = open_one(m->files[n], compression_mode(m) == 'f', max_message, &dbs[n],
				  err)) < 0 && m->file_count > 1) {
			char why[sizeof err->message];
			memcpy(why, err->message, sizeof why);
			dao_error_set(err, r, "%s: file %u of the %u its metadata.yaml lists (a split bag plays only "
				      "with all its files): %s", dir,
				      n + 1, m->file_count, why);
		}
	if (r < 0) {
		for (uint32_t f = 0; f + 1 < n; f++)
			dao_db3_close(dbs[f]);
	} else {
		r = dao_db3_multi_open(dbs, m->file_count,
				       m->file_count > 1 ? dir : m->files[0], out, err);
		if (r == 0 && compression_mode(m) == 'm')
			dao_db3_multi_zstd_messages(*out, max_message);
	}
	free(dbs);
	return r;
}

/* A rosbag2 directory: MCAP storage by the mcap source, sqlite3 by db3_multi_store. */
static int open_dir(struct dao_ros_uri *u, const struct dao_source_options *opts,
		    uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct dao_rosbag2_meta m;
	struct dao_db3_multi *db;
	int r = dao_rosbag2_metadata(u->path, &m, err);
	if (r < 0)
		return r;
	if ((r = check_meta(u->path, &m, err)) == 0 && !strcmp(m.storage, "mcap")) {
		char *p = strdup(m.files[0]);
		if (!p) {
			r = dao_error_set(err, -ENOMEM, "out of memory");
		} else {
			free(u->path);
			u->path = p;
			r = dao_mcap_source_open_path(u, opts, max_pixels, state, err);
		}
	} else if (r == 0 && (r = open_split(u->path, &m, 4 * max_pixels + (1u << 20), &db,
					     err)) == 0) {
		r = dao_ros2_source_open(&db3_multi_store, db, u, "db3", opts, max_pixels, state,
					 err);
	}
	dao_rosbag2_meta_free(&m);
	return r;
}

int dao_db3_source_open(const char *uri, const struct dao_source_options *opts,
			uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct dao_ros_uri u;
	struct stat st;
	struct dao_db3 *db;
	struct dao_db3_multi *bag;
	int r = dao_ros_uri_parse(uri, "db3", &u, err);
	if (r == 0 && stat(u.path, &st) == 0 && S_ISDIR(st.st_mode))
		r = open_dir(&u, opts, max_pixels, state, err);
	/* a message holds one image (up to 4 bytes a pixel) and its header */
	else if (r == 0 && (r = dao_db3_open(u.path, 4 * max_pixels + (1u << 20), &db, err)) == 0 &&
		 (r = dao_db3_multi_open(&db, 1, u.path, &bag, err)) == 0)
		r = dao_ros2_source_open(&db3_multi_store, bag, &u, "db3", opts, max_pixels, state,
					 err);
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
	.frame_pose = dao_ros2_source_frame_pose,
};

const struct dao_plugin dao_builtin_db3_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "db3",
	.description = "rosbag2 sqlite3 bags (.db3, or a bag directory with metadata.yaml): the "
		       "mcap source's messages (CDR Image, compressedDepth, CameraInfo, colour; "
		       "Foxglove schemas; camera poses from tf, odometry or an IMU); "
		       "FILE.db3|DIR[?topic=T][&unit=M][&color=C][&pose_frame=F][&pose_topic=O]",
	.source = &db3_source_ops,
};
