/* SPDX-License-Identifier: MIT */
#ifndef DAO_DB3_DB3_READER_H
#define DAO_DB3_DB3_READER_H

/*
 * A reader of rosbag2's sqlite3 storage (.db3, ROS 2 Foxy to Humble's
 * default), through libsqlite3.  The database holds two tables:
 *   topics(id INTEGER, name TEXT, type TEXT, serialization_format TEXT,
 *          offered_qos_profiles TEXT)
 *   messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER,
 *            data BLOB)      timestamp: ns, with an index on it
 * The file is opened read-only and immutable (no lock, no journal: a file
 * that changes under the reader is not supported).  Opening reads the
 * topics and, through the timestamp index, the id and time of every message
 * (16 bytes each; at most DAO_DB3_MAX_MESSAGES); a message's data is read
 * when asked for, by id.  Every value's type is checked (a column of
 * another type, a topic_id no topic has, a blob over the limit is an error
 * naming the file, the table and the row).  One thread at a time per reader.
 */
#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

#define DAO_DB3_MAX_MESSAGES (1u << 25)
#define DAO_DB3_MAX_TOPICS 4096

struct dao_db3;

struct dao_db3_topic {
	const char *name;                 /* "/camera/depth/image_raw" */
	const char *type;                 /* "sensor_msgs/msg/Image" */
	const char *serialization_format; /* "cdr" */
	uint32_t message_count;
};

/*
 * Opens `path`; a message's data larger than `max_message` bytes is refused
 * when read.  -ENOENT/-EACCES (cannot open), -EINVAL (not a rosbag2
 * database: no such table or column, a value of another type), -EFBIG (over
 * a limit), -EIO (sqlite could not read it), -ENOMEM.
 */
int dao_db3_open(const char *path, uint64_t max_message, struct dao_db3 **out,
		 struct dao_error *err);
void dao_db3_close(struct dao_db3 *db);

const char *dao_db3_path(const struct dao_db3 *db);
uint32_t dao_db3_topic_count(const struct dao_db3 *db);
/* NULL if i >= count.  Topics are in the order of their id. */
const struct dao_db3_topic *dao_db3_topic(const struct dao_db3 *db, uint32_t i);

/*
 * Message `i` (timestamp order, then id) of topic `topic`: its data, valid
 * until the next call on the reader, and its timestamp (ns).
 */
int dao_db3_read_message(struct dao_db3 *db, uint32_t topic, uint32_t i, const uint8_t **data,
			 uint64_t *len, uint64_t *log_time, struct dao_error *err);
/* The timestamp of message `i` of a topic, without reading it; 0 if there is none. */
uint64_t dao_db3_message_time(const struct dao_db3 *db, uint32_t topic, uint32_t i);

/*
 * A rosbag2 directory's metadata.yaml (rosbag2_bagfile_information:
 * storage_identifier, compression_format, compression_mode,
 * relative_file_paths): the storage ("sqlite3", "mcap"), the compression
 * ("" when none) and the files in their order, joined to `dir` (at most
 * DAO_ROSBAG2_MAX_FILES; each a name inside the directory).  -EINVAL with a
 * message when the file is not such metadata; dao_rosbag2_meta_free() after
 * a success.
 */
#define DAO_ROSBAG2_MAX_FILES 4096

struct dao_rosbag2_meta {
	char storage[64];
	char compression_format[32]; /* "", "zstd" */
	char compression_mode[16];   /* "", "FILE", "MESSAGE" */
	uint32_t file_count;
	char **files;
};

int dao_rosbag2_metadata(const char *dir, struct dao_rosbag2_meta *m, struct dao_error *err);
void dao_rosbag2_meta_free(struct dao_rosbag2_meta *m);

/*
 * The files of a split bag as one reader's topics and messages: a topic is
 * the same name (and type) in every file, its messages those of the files in
 * their order, which must be in time order.  The readers are taken (closed by
 * dao_db3_multi_close, also on failure).  `path` names the bag in messages.
 */
struct dao_db3_multi;
int dao_db3_multi_open(struct dao_db3 **dbs, uint32_t n, const char *path,
		       struct dao_db3_multi **out, struct dao_error *err);
/*
 * Messages compressed one by one (rosbag2's compression_mode message, zstd):
 * each decompressed when read, to at most max bytes.
 */
void dao_db3_multi_zstd_messages(struct dao_db3_multi *m, uint64_t max);
void dao_db3_multi_close(struct dao_db3_multi *m);
const char *dao_db3_multi_path(const struct dao_db3_multi *m);
uint32_t dao_db3_multi_topic_count(const struct dao_db3_multi *m);
const struct dao_db3_topic *dao_db3_multi_topic(const struct dao_db3_multi *m, uint32_t i);
int dao_db3_multi_read_message(struct dao_db3_multi *m, uint32_t topic, uint32_t i,
			       const uint8_t **data, uint64_t *len, uint64_t *log_time,
			       struct dao_error *err);
uint64_t dao_db3_multi_message_time(const struct dao_db3_multi *m, uint32_t topic, uint32_t i);

/*
 * rosbag2's zstd compression (db3_zstd.c).  dao_db3_unzstd_file decompresses
 * the file src into a new temporary file in $TMPDIR (or /tmp), its name into
 * tmp (cap bytes), to at most dao_db3_unzstd_limit(its size) bytes:
 * -EOVERFLOW beyond (a zstd bomb), -EINVAL for data that is not zstd or cut short; the
 * caller unlinks tmp.  dao_db3_unzstd_message decompresses one message into
 * *buf (grown as needed, *cap its size) when its frame says a size of at most
 * max bytes.
 */
#define DAO_DB3_UNZSTD_RATIO 64             /* decompressed per compressed byte, at most */
#define DAO_DB3_UNZSTD_MIN (64ull << 20)    /* ... but this much for any file */
#define DAO_DB3_UNZSTD_MAX (16ull << 30)    /* ... and never more */
uint64_t dao_db3_unzstd_limit(uint64_t compressed);
int dao_db3_unzstd_file(const char *src, char *tmp, size_t cap, struct dao_error *err);
int dao_db3_unzstd_message(const uint8_t *in, uint64_t len, uint64_t max, uint8_t **buf,
			   uint64_t *cap, uint64_t *out, struct dao_error *err);

#endif
