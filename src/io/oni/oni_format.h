/* SPDX-License-Identifier: MIT */
/*
 * The .oni record stream (OpenNI 1.x/2.x "NI10" files), as laid out by
 * OpenNI's recorder and read by its file driver.  All integers little-endian,
 * structures packed.
 *
 *   file header (24 bytes): "NI10", version {u8 major, u8 minor,
 *       u16 maintenance, u32 build}, u64 global max timestamp, u32 max node id
 *   record header (28 bytes; 24 with a u32 undo position before 1.0.1.0):
 *       u32 magic "NIR\0", u32 type, u32 node id, u32 fields size (header
 *       included), u32 payload size, u64 undo position (previous record of
 *       the same kind, 0 if none)
 *   fields, then payload.  Strings are u32 length (with the NUL), then bytes.
 */
#ifndef DAO_ONI_FORMAT_H
#define DAO_ONI_FORMAT_H

#include <stdint.h>
#include <string.h>

#define ONI_FILE_HEADER_SIZE 24
#define ONI_RECORD_MAGIC 0x0052494Eu
#define ONI_RECORD_HEADER_SIZE 28
#define ONI_RECORD_HEADER_SIZE_OLD32 24

enum oni_record_type {
	ONI_REC_NODE_ADDED_1_0_0_4 = 0x02,
	ONI_REC_INT_PROPERTY = 0x03,
	ONI_REC_REAL_PROPERTY = 0x04,
	ONI_REC_STRING_PROPERTY = 0x05,
	ONI_REC_GENERAL_PROPERTY = 0x06,
	ONI_REC_NODE_REMOVED = 0x07,
	ONI_REC_NODE_DATA_BEGIN = 0x08,
	ONI_REC_NODE_STATE_READY = 0x09,
	ONI_REC_NEW_DATA = 0x0A,
	ONI_REC_END = 0x0B,
	ONI_REC_NODE_ADDED_1_0_0_5 = 0x0C,
	ONI_REC_NODE_ADDED = 0x0D,
	ONI_REC_SEEK_TABLE = 0x0E,
};

/* XnProductionNodeType values of the nodes that carry images. */
#define ONI_NODE_TYPE_DEVICE 1
#define ONI_NODE_TYPE_DEPTH 2
#define ONI_NODE_TYPE_IMAGE 3
#define ONI_NODE_TYPE_IR 5

#define ONI_FOURCC(a, b, c, d) \
	((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) | ((uint32_t)(d) << 24))
#define ONI_CODEC_NONE ONI_FOURCC('N', 'O', 'N', 'E')
#define ONI_CODEC_16Z ONI_FOURCC('1', '6', 'z', 'P')
#define ONI_CODEC_16ZT ONI_FOURCC('1', '6', 'z', 'T')
#define ONI_CODEC_JPEG ONI_FOURCC('J', 'P', 'E', 'G')
#define ONI_CODEC_8Z ONI_FOURCC('I', 'm', '8', 'z')

/* Seek table entry: u64 timestamp, u32 configuration id, u64 record position. */
#define ONI_SEEK_ENTRY_SIZE 20

static inline uint16_t oni_rd16(const uint8_t *p)
{
	return (uint16_t)(p[0] | (p[1] << 8));
}

static inline uint32_t oni_rd32(const uint8_t *p)
{
	return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
	       ((uint32_t)p[3] << 24);
}

static inline uint64_t oni_rd64(const uint8_t *p)
{
	return (uint64_t)oni_rd32(p) | ((uint64_t)oni_rd32(p + 4) << 32);
}

static inline double oni_rdf64(const uint8_t *p)
{
	uint64_t u = oni_rd64(p);
	double d;
	memcpy(&d, &u, sizeof(d));
	return d;
}

static inline void oni_wr16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
}

static inline void oni_wr32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (uint8_t)(v >> (8 * i));
}

static inline void oni_wr64(uint8_t *p, uint64_t v)
{
	for (int i = 0; i < 8; i++)
		p[i] = (uint8_t)(v >> (8 * i));
}

#endif
