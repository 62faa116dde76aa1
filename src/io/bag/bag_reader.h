/* SPDX-License-Identifier: MIT */
#ifndef DAO_BAG_BAG_READER_H
#define DAO_BAG_BAG_READER_H

/*
 * A reader of ROS 1 bag files, format 2.0 (http://wiki.ros.org/Bags/Format/2.0):
 * chunks stored uncompressed, bz2 or lz4 (the LZ4 frame format of roslz4).
 * Opening reads the bag header, the connection and chunk info records at
 * its index position and the index data records after every chunk, never
 * the chunks themselves (a bag without an index is scanned instead): a
 * topic's messages are then read in time order, by position, each from its
 * (decompressed, cached) chunk.  Every length and
 * offset is checked against its record and the file; errors name the file
 * and the byte offset.  One thread at a time per reader.
 */
#include <stdint.h>

#include <depthao/error.h>

struct dao_bag;

struct dao_bag_topic {
	const char *name;       /* "/camera/depth/image_raw" */
	const char *type;       /* "sensor_msgs/Image" */
	uint32_t message_count; /* over all its connections */
};

/*
 * Opens `path`.  A chunk larger than `max_chunk` bytes (uncompressed) is
 * refused when it is read.  -ENOENT/-EACCES (cannot open), -EINVAL (not a
 * bag, corrupt, unindexed without a complete chunk), -EIO, -ENOMEM.
 */
int dao_bag_open(const char *path, uint64_t max_chunk, struct dao_bag **out,
		 struct dao_error *err);
void dao_bag_close(struct dao_bag *bag);

const char *dao_bag_path(const struct dao_bag *bag);
/*
 * NULL, or a line saying the bag had no index (its recording was not
 * finished) and how far its chunks could be read: such a bag is read by
 * scanning its chunks, up to the first one cut short or damaged.
 */
const char *dao_bag_warning(const struct dao_bag *bag);
uint32_t dao_bag_topic_count(const struct dao_bag *bag);
/* NULL if i >= count. */
const struct dao_bag_topic *dao_bag_topic(const struct dao_bag *bag, uint32_t i);
/* The index of a topic by name (the first of that name), or -1. */
int dao_bag_find_topic(const struct dao_bag *bag, const char *name);

/*
 * Message `i` (time order) of topic `topic`: its serialized data (valid
 * until the next call on the reader) and the time it was recorded, in ns.
 */
int dao_bag_read_message(struct dao_bag *bag, uint32_t topic, uint32_t i, const uint8_t **data,
			 uint32_t *len, uint64_t *time_ns, struct dao_error *err);

/*
 * The time message `i` of topic `topic` was recorded (ns), from the index,
 * without reading it; 0 if there is no such message.  Messages are in this
 * order.
 */
uint64_t dao_bag_message_time(const struct dao_bag *bag, uint32_t topic, uint32_t i);

#endif
