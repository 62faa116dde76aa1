/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_MCAP_WRITER_H
#define DAO_MCAP_MCAP_WRITER_H

/*
 * An MCAP writer (https://mcap.dev/spec, record layout in mcap_format.h):
 * magic, Header, the Schemas and Channels (all added before the first
 * message), Chunks each followed by its Message Indexes, Data End, then the
 * summary (Schemas, Channels, Statistics, Chunk Indexes), its Summary
 * Offsets, Footer and magic.  Chunks are compressed with zstd, lz4 (frame
 * format) or not at all, and carry the CRC of their records; Data End and
 * the Footer carry the CRCs of the data and summary sections.
 *
 * What survives what:
 *   - The file only grows by whole records at its own name, written with
 *     pwritev straight to the kernel: a process killed at any moment (kill
 *     -9) leaves a file that a linear scan reads up to its last complete
 *     chunk.  What is lost is the chunk being built: at most `chunk_size`
 *     bytes of messages, and at most DAO_MCAP_CHUNK_MAX_AGE_MS of them (a
 *     message that comes later than that after the chunk's first closes the
 *     chunk first; dao_mcap_writer_flush() closes it at once).
 *   - The file is synced (fdatasync) after a chunk when the last sync is
 *     DAO_MCAP_SYNC_INTERVAL_MS or more ago, at flush and at finish.
 *   - A full disk: before a message is taken into the chunk, the space the
 *     chunk (compressed in the worst case), its indexes and the summary
 *     will need is reserved in the file system (fallocate, KEEP_SIZE: the
 *     file's size does not change).  When that fails the message is refused
 *     (-ENOSPC) and everything accepted before still fits: finish writes it
 *     and the summary.  On file systems without fallocate a failed chunk
 *     write is cut off again (ftruncate) and reported; the file keeps its
 *     complete chunks.
 * Memory: the chunk buffer (chunk_size, or one larger message), its
 * compressed bound, the message index entries of one chunk and ~100 bytes
 * per chunk written for the summary's chunk index.
 */
#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

#define DAO_MCAP_CHUNK_MAX_AGE_MS 1000
#define DAO_MCAP_SYNC_INTERVAL_MS 1000
#define DAO_MCAP_DEFAULT_CHUNK_SIZE (4u << 20)
#define DAO_MCAP_MAX_CHANNELS 16
/* one message's data at most (a 16k x 16k rgb8 image is 768 MiB) */
#define DAO_MCAP_MAX_MESSAGE ((size_t)1 << 30)

enum dao_mcap_compression {
	DAO_MCAP_COMPRESS_ZSTD = 0,
	DAO_MCAP_COMPRESS_LZ4,
	DAO_MCAP_COMPRESS_NONE,
};

struct dao_mcap_writer_options {
	enum dao_mcap_compression compression;
	int zstd_level;         /* 0: 1 */
	uint64_t chunk_size;    /* uncompressed bytes that close a chunk; 0: the default */
	int overwrite;          /* replace an existing file (else -EEXIST); the caller checks
				   dao_output_file_check_replaceable() first */
	const char *profile;    /* Header profile ("ros2") */
};

struct dao_mcap_writer;

/* Creates the file (O_EXCL unless overwrite) and writes magic and Header. */
int dao_mcap_writer_open(const char *path, const struct dao_mcap_writer_options *o,
			 struct dao_mcap_writer **out, struct dao_error *err);
/* Before the first message: a schema (id 1, 2, ...) and a channel (id 0, 1, ...). */
int dao_mcap_writer_add_schema(struct dao_mcap_writer *w, const char *name, const char *encoding,
			       const char *data, uint16_t *id, struct dao_error *err);
int dao_mcap_writer_add_channel(struct dao_mcap_writer *w, uint16_t schema_id, const char *topic,
				const char *message_encoding, uint16_t *id, struct dao_error *err);
/*
 * A message of `len` data bytes: *data points at them in the chunk being
 * built, for the caller to fill before the next call on the writer.  0, or
 * < 0 with a message (-ENOSPC: refused, the disk is full; the writer stays
 * usable and what it accepted is kept).
 */
int dao_mcap_writer_message(struct dao_mcap_writer *w, uint16_t channel, uint64_t log_time,
			    uint64_t publish_time, size_t len, uint8_t **data,
			    struct dao_error *err);
/* Writes the chunk being built (if any) and syncs the file. */
int dao_mcap_writer_flush(struct dao_mcap_writer *w, struct dao_error *err);
/* Messages accepted; chunks written. */
uint64_t dao_mcap_writer_messages(const struct dao_mcap_writer *w);
uint64_t dao_mcap_writer_chunks(const struct dao_mcap_writer *w);
/* The last chunk, the summary and footer; syncs, closes and frees (also after an error:
 * what was written stays readable).  0 or < 0. */
int dao_mcap_writer_finish(struct dao_mcap_writer *w, struct dao_error *err);
/* Closes, removes the file and frees (a recording without messages). */
void dao_mcap_writer_abort(struct dao_mcap_writer *w);

#endif
