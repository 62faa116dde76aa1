/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_MCAP_FORMAT_H
#define DAO_MCAP_MCAP_FORMAT_H

/*
 * The MCAP container format (https://mcap.dev/spec, version 0): its magic,
 * record opcodes and the layout of the records a reader or writer of depth
 * recordings uses, shared by the reader (mcap_reader.c) and a writer.
 *
 *   file:    magic, Header, data section records, Data End, summary
 *            section records, summary offset records, Footer, magic
 *   record:  opcode u8, length u64, `length` bytes of content
 *
 * Integers are little-endian.  In content: a string is a u32 byte length
 * then UTF-8 (no NUL); "bytes4" a u32 length then bytes; a map a u32 byte
 * length then its entries; an array likewise.  A field at the end of a
 * record (a Message's data, a Chunk's records) runs to the record's end
 * or has a u64 length.  The parsers below take a record's content and its
 * length, check every length against it, and return 0 or -EINVAL; the
 * strings and byte fields they give point into the content (not
 * NUL-terminated: ptr + len).
 */
#include <stddef.h>
#include <stdint.h>

#define DAO_MCAP_MAGIC "\x89MCAP0\r\n"
#define DAO_MCAP_MAGIC_LEN 8
/* opcode u8 + length u64 */
#define DAO_MCAP_RECORD_HEADER 9

enum dao_mcap_opcode {
	DAO_MCAP_OP_HEADER = 0x01,
	DAO_MCAP_OP_FOOTER = 0x02,
	DAO_MCAP_OP_SCHEMA = 0x03,
	DAO_MCAP_OP_CHANNEL = 0x04,
	DAO_MCAP_OP_MESSAGE = 0x05,
	DAO_MCAP_OP_CHUNK = 0x06,
	DAO_MCAP_OP_MESSAGE_INDEX = 0x07,
	DAO_MCAP_OP_CHUNK_INDEX = 0x08,
	DAO_MCAP_OP_ATTACHMENT = 0x09,
	DAO_MCAP_OP_ATTACHMENT_INDEX = 0x0A,
	DAO_MCAP_OP_STATISTICS = 0x0B,
	DAO_MCAP_OP_METADATA = 0x0C,
	DAO_MCAP_OP_METADATA_INDEX = 0x0D,
	DAO_MCAP_OP_SUMMARY_OFFSET = 0x0E,
	DAO_MCAP_OP_DATA_END = 0x0F,
};

/* Footer: the whole record is fixed (opcode, length 20, content) then the magic. */
#define DAO_MCAP_FOOTER_CONTENT 20
#define DAO_MCAP_FOOTER_RECORD (DAO_MCAP_RECORD_HEADER + DAO_MCAP_FOOTER_CONTENT)

struct dao_mcap_str {
	const char *ptr;
	uint32_t len;
};

struct dao_mcap_header {        /* 0x01 */
	struct dao_mcap_str profile; /* "ros2", "" ... */
	struct dao_mcap_str library;
};

struct dao_mcap_footer {        /* 0x02 */
	uint64_t summary_start;        /* 0: no summary section */
	uint64_t summary_offset_start; /* 0: no summary offset section */
	uint32_t summary_crc;          /* of summary_start .. this field; 0: none */
};

struct dao_mcap_schema {        /* 0x03 */
	uint16_t id;                 /* 0 is invalid (a channel without schema) */
	struct dao_mcap_str name;    /* "sensor_msgs/msg/Image" */
	struct dao_mcap_str encoding; /* "ros2msg", "jsonschema", "protobuf", "" */
	const uint8_t *data;         /* bytes4: the definition */
	uint32_t data_len;
};

struct dao_mcap_channel {       /* 0x04 */
	uint16_t id;
	uint16_t schema_id;          /* 0: none */
	struct dao_mcap_str topic;
	struct dao_mcap_str message_encoding; /* "cdr", "json", "protobuf" ... */
	/* metadata: map<string, string>, not parsed */
};

/* Message (0x05): channel u16, sequence u32, log_time u64, publish_time u64, data. */
#define DAO_MCAP_MESSAGE_FIXED 22
struct dao_mcap_message {
	uint16_t channel_id;
	uint32_t sequence;
	uint64_t log_time, publish_time; /* ns */
	const uint8_t *data;             /* to the end of the record */
	uint64_t data_len;
};

struct dao_mcap_chunk {         /* 0x06 */
	uint64_t message_start_time, message_end_time;
	uint64_t uncompressed_size;
	uint32_t uncompressed_crc;   /* crc32 of the uncompressed records; 0: none */
	struct dao_mcap_str compression; /* "" (none), "zstd", "lz4" (frame format) */
	const uint8_t *records;      /* u64 length, then the (compressed) records */
	uint64_t records_len;
};
/* A chunk's fixed fields before `compression`, and what follows it: */
#define DAO_MCAP_CHUNK_FIXED 28

/* Message Index (0x07): channel u16, then an array (u32 byte length) of
 * (log_time u64, offset u64 into the chunk's uncompressed records). */
struct dao_mcap_message_index {
	uint16_t channel_id;
	const uint8_t *entries;      /* 16 bytes each */
	uint32_t count;
};

/* Chunk Index (0x08). */
struct dao_mcap_chunk_index {
	uint64_t message_start_time, message_end_time;
	uint64_t chunk_start_offset;  /* of the chunk record in the file */
	uint64_t chunk_length;        /* of the whole record */
	const uint8_t *index_offsets; /* map<u16 channel, u64 offset>, 10 bytes each */
	uint32_t index_offsets_count;
	uint64_t message_index_length; /* bytes of Message Index records after the chunk */
	struct dao_mcap_str compression;
	uint64_t compressed_size, uncompressed_size;
};

/* Statistics (0x0B): the counts (the per-channel message counts not parsed). */
struct dao_mcap_statistics {
	uint64_t message_count;
	uint16_t schema_count;
	uint32_t channel_count, attachment_count, metadata_count, chunk_count;
	uint64_t message_start_time, message_end_time;
};

struct dao_mcap_summary_offset { /* 0x0E */
	uint8_t group_opcode;
	uint64_t group_start, group_length;
};

/* Data End (0x0F): data_section_crc u32, crc32 of the file up to this record; 0: none. */
#define DAO_MCAP_DATA_END_CONTENT 4

static inline uint16_t dao_mcap_rd16(const uint8_t *p)
{
	return (uint16_t)(p[0] | p[1] << 8);
}

static inline uint32_t dao_mcap_rd32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static inline uint64_t dao_mcap_rd64(const uint8_t *p)
{
	return (uint64_t)dao_mcap_rd32(p) | (uint64_t)dao_mcap_rd32(p + 4) << 32;
}

static inline void dao_mcap_wr16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
}

static inline void dao_mcap_wr32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (uint8_t)(v >> 8 * i);
}

static inline void dao_mcap_wr64(uint8_t *p, uint64_t v)
{
	for (int i = 0; i < 8; i++)
		p[i] = (uint8_t)(v >> 8 * i);
}

/* Record content parsers (c: the content, n: its length). */
int dao_mcap_parse_header(const uint8_t *c, uint64_t n, struct dao_mcap_header *h);
int dao_mcap_parse_footer(const uint8_t *c, uint64_t n, struct dao_mcap_footer *f);
int dao_mcap_parse_schema(const uint8_t *c, uint64_t n, struct dao_mcap_schema *s);
int dao_mcap_parse_channel(const uint8_t *c, uint64_t n, struct dao_mcap_channel *ch);
int dao_mcap_parse_message(const uint8_t *c, uint64_t n, struct dao_mcap_message *m);
int dao_mcap_parse_chunk(const uint8_t *c, uint64_t n, struct dao_mcap_chunk *ch);
int dao_mcap_parse_message_index(const uint8_t *c, uint64_t n, struct dao_mcap_message_index *mi);
int dao_mcap_parse_chunk_index(const uint8_t *c, uint64_t n, struct dao_mcap_chunk_index *ci);
int dao_mcap_parse_statistics(const uint8_t *c, uint64_t n, struct dao_mcap_statistics *s);
int dao_mcap_parse_summary_offset(const uint8_t *c, uint64_t n,
				  struct dao_mcap_summary_offset *so);

/* 1 if a string field equals the C string s. */
int dao_mcap_str_eq(struct dao_mcap_str a, const char *s);

/* crc32 (zlib's polynomial): crc = dao_mcap_crc32(0, ...) then continued. */
uint32_t dao_mcap_crc32(uint32_t crc, const void *data, size_t n);

#endif
