/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_MCAP_READER_H
#define DAO_MCAP_MCAP_READER_H

/*
 * A reader of MCAP files (mcap_format.h): chunked (chunks uncompressed,
 * zstd or lz4) or not.  Opening reads the header and, when the file ends
 * with a footer whose summary holds chunk indexes, the summary's schemas,
 * channels and chunk indexes and the message indexes after each chunk:
 * the chunks themselves are read only when one of their messages is.
 * Otherwise (no summary, or an unchunked file, or a recording cut short)
 * the data section is scanned record by record up to its Data End record,
 * or up to the first record cut short (with a warning), checking the data
 * section's CRC when it ends with one.  Every chunk's CRC is checked when
 * it is decompressed.  A channel's messages are then read in log-time
 * order, each from its (decompressed, cached) chunk or from the file.
 * Every length and offset is checked against its record and the file;
 * errors name the file and the byte.  One thread at a time per reader.
 */
#include <stdint.h>

#include <depthao/error.h>

struct dao_mcap;

/* A channel: a topic with its message encoding and schema. */
struct dao_mcap_topic {
	const char *name;            /* "/camera/depth/image_raw" */
	const char *schema;          /* "sensor_msgs/msg/Image" ("" without a schema) */
	const char *schema_encoding; /* "ros2msg", "jsonschema" ... */
	const char *encoding;        /* message encoding: "cdr", "json" ... */
	uint32_t message_count;
};

/*
 * Opens `path`.  A chunk or record larger than `max_chunk` bytes
 * (uncompressed) is refused.  -ENOENT/-EACCES (cannot open), -EINVAL (not
 * MCAP, corrupt, no complete record), -EFBIG (over a limit), -EIO, -ENOMEM.
 */
int dao_mcap_open(const char *path, uint64_t max_chunk, struct dao_mcap **out,
		  struct dao_error *err);
void dao_mcap_close(struct dao_mcap *m);

const char *dao_mcap_path(const struct dao_mcap *m);
/* NULL, or a line saying the file was cut short and how far it was read. */
const char *dao_mcap_warning(const struct dao_mcap *m);
/* 1 if the summary's indexes were used, 0 if the data section was scanned. */
int dao_mcap_indexed(const struct dao_mcap *m);
uint32_t dao_mcap_topic_count(const struct dao_mcap *m);
/* NULL if i >= count. */
const struct dao_mcap_topic *dao_mcap_topic(const struct dao_mcap *m, uint32_t i);
/* The index of a topic by name (the first channel of that name), or -1. */
int dao_mcap_find_topic(const struct dao_mcap *m, const char *name);

/*
 * Message `i` (log-time order) of topic `topic`: its data (valid until the
 * next call on the reader) and its log time (ns).
 */
int dao_mcap_read_message(struct dao_mcap *m, uint32_t topic, uint32_t i, const uint8_t **data,
			  uint64_t *len, uint64_t *log_time, struct dao_error *err);
/* The log time of message `i` of a topic, without reading it; 0 if there is none. */
uint64_t dao_mcap_message_time(const struct dao_mcap *m, uint32_t topic, uint32_t i);

#endif
