/* SPDX-License-Identifier: MIT */
/* Part of libdepthao-io (pkg-config depthao-io, <depthao/io.h>), not of the AO core libdepthao. */
/*
 * OpenNI recordings (.oni), read and written without OpenNI.
 *
 * The format is OpenNI's "NI10" record stream (file versions 1.0.0.4 to
 * 1.0.1.0): a 24-byte header, then records (node added, properties, state
 * ready, data begin, new data, seek table, end).  Depth nodes are read and
 * written with the codecs NONE (raw little-endian uint16), 16zP (delta
 * coding, "16z") and 16zT (16z over an embedded table of the values that
 * occur); other nodes (JPEG colour, IR) are listed but not decoded.
 *
 * Files this writer makes play in OpenNI2's own file driver frame-exactly;
 * the reader decodes real recordings pixel-identically to OpenNI2 and turns
 * every inconsistency (wrong magic, frames larger than declared, corrupt 16z
 * streams) into -EINVAL or -EIO with a message, never a crash.  A recording
 * that was never finished (a crash, kill -9, power loss, a full disk) is
 * recovered up to its last complete frame, with a warning.
 */
#ifndef DEPTHAO_ONI_H
#define DEPTHAO_ONI_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>
#include <depthao/frame.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Codecs of .oni streams. */
enum dao_oni_codec {
	DAO_ONI_CODEC_NONE = 0, /* "NONE": raw uint16 */
	DAO_ONI_CODEC_16Z,      /* "16zP" */
	DAO_ONI_CODEC_16ZT,     /* "16zT" */
	DAO_ONI_CODEC_JPEG,     /* "JPEG" (colour) */
	DAO_ONI_CODEC_8Z,       /* "Im8z" (listed, not decoded) */
	DAO_ONI_CODEC_OTHER,
};

/* Kinds of .oni stream. */
enum dao_oni_sensor {
	DAO_ONI_SENSOR_OTHER = 0,
	DAO_ONI_SENSOR_DEPTH,
	DAO_ONI_SENSOR_COLOR,
	DAO_ONI_SENSOR_IR,
};

/* OpenNI2 pixel formats of depth streams (OniPixelFormat values). */
#define DAO_ONI_PIXEL_DEPTH_1_MM 100
/* depth in 100 um counts */
#define DAO_ONI_PIXEL_DEPTH_100_UM 101
/* ... and of colour streams (OpenNI 1's xnPixelFormat is mapped to these). */
#define DAO_ONI_PIXEL_RGB888 200
#define DAO_ONI_PIXEL_YUV422 201     /* U Y0 V Y1 */
/* 8-bit grey */
#define DAO_ONI_PIXEL_GRAY8 202
/* JPEG-compressed colour */
#define DAO_ONI_PIXEL_JPEG 204
#define DAO_ONI_PIXEL_YUYV 205       /* Y0 U Y1 V */

/* One stream (node) of an .oni recording. */
struct dao_oni_stream_info {
	char name[64];               /* node name, e.g. "Depth1" */
	/* depth, colour, IR or another node */
	enum dao_oni_sensor sensor;
	/* how its frames are compressed */
	enum dao_oni_codec codec;
	char codec_fourcc[5];        /* as stored, e.g. "16zT" */
	uint32_t width, height, fps; /* from xnMapOutputMode (0 if absent) */
	uint32_t frame_count;        /* frames found in the file */
	int pixel_format;            /* OniPixelFormat; depth: 100 (1 mm) or 101 (100 um);
					colour: DAO_ONI_PIXEL_RGB888 ... (0 if not recorded) */
	float depth_unit;            /* metres per count (depth streams), else 0 */
	uint32_t max_depth;          /* xnDeviceMaxDepth in counts, 0 if absent */
	int has_fov;                 /* xnFOV present */
	double hfov, vfov;           /* radians */
	int mirrored;                /* xnMirror */
	int registered;              /* AlternativeViewPoint: depth registered to colour */
	/* timestamps of the first and last frame, microseconds */
	uint64_t first_timestamp_us, last_timestamp_us;
};

/* --- reading ---------------------------------------------------------- */

struct dao_oni_reader;

/*
 * Opens a recording and indexes it (one pass over the record headers; frame
 * data is read on demand).  The frame count, seek table and end record are
 * not needed: a file that ends without an end record, in a record cut short
 * or in zeros (an unfinished recording) opens with the frames before that
 * and a warning (dao_oni_reader_warning).  Depth streams with frames larger
 * than DAO_DEFAULT_MAX_PIXELS (width x height) are refused before their
 * decode buffers are allocated.  Errors: -ENOENT/-EACCES (cannot open),
 * -EINVAL (not an .oni file, unsupported version, corrupt structure, an
 * unfinished file without one complete frame), -EFBIG (over the pixel
 * limit), -ENOMEM.
 */
DAO_API int dao_oni_reader_open(const char *path, struct dao_oni_reader **out,
				struct dao_error *err);
/* dao_oni_reader_open() with another pixel limit (0 = DAO_DEFAULT_MAX_PIXELS). */
DAO_API int dao_oni_reader_open_limited(const char *path, uint64_t max_pixels,
					struct dao_oni_reader **out, struct dao_error *err);
/* Closes the reader and frees it; NULL-safe. */
DAO_API void dao_oni_reader_close(struct dao_oni_reader *reader);

/*
 * NULL for a finished recording; for an unfinished one that was recovered, a
 * one-line message naming the file, the frames recovered and what was left
 * out, for the caller to show as a warning.
 */
DAO_API const char *dao_oni_reader_warning(const struct dao_oni_reader *reader);

/* The number of streams in the recording. */
DAO_API uint32_t dao_oni_reader_stream_count(const struct dao_oni_reader *reader);
/* Stream `index` (< dao_oni_reader_stream_count()), NULL if out of range. */
DAO_API const struct dao_oni_stream_info *
dao_oni_reader_stream(const struct dao_oni_reader *reader, uint32_t index);

/* Index of the first depth stream, or -ENOENT (with a message) if there is none. */
DAO_API int dao_oni_reader_depth_stream(const struct dao_oni_reader *reader,
					struct dao_error *err);

/*
 * Decodes frame `frame` (0-based, < frame_count) of depth stream `stream`
 * into `out`, a caller-owned DAO_PIXFMT_DEPTH16 frame of the stream's size
 * (any stride); sets out->depth_unit, ->timestamp_ns and ->sequence (the
 * recorded 1-based frame number).  Any frame may be read in any order; no
 * allocation happens here.  Errors: -EINVAL (bad arguments, corrupt frame,
 * with the frame number in the message), -EIO (read error or file shrank).
 */
DAO_API int dao_oni_reader_read_depth(struct dao_oni_reader *reader, uint32_t stream,
				      uint32_t frame, struct dao_frame *out,
				      struct dao_error *err);

/* Index of the first colour stream, or -ENOENT (with a message) if there is none. */
DAO_API int dao_oni_reader_color_stream(const struct dao_oni_reader *reader,
					struct dao_error *err);

/*
 * 0 if colour stream `stream` can be decoded (JPEG, or raw RGB888, YUV422,
 * YUYV, GRAY8 of its declared size), else -ENOTSUP with a message saying why
 * (e.g. the Im8z codec, a missing size).
 */
DAO_API int dao_oni_reader_color_usable(const struct dao_oni_reader *reader, uint32_t stream,
					struct dao_error *err);

/*
 * Decodes frame `frame` of colour stream `stream` into `out`, a caller-owned
 * DAO_PIXFMT_RGB24 frame of the stream's size (any stride); sets
 * out->timestamp_ns and ->sequence.  JPEG decoding allocates inside
 * libjpeg; raw formats do not allocate.  Errors as dao_oni_reader_read_depth.
 */
DAO_API int dao_oni_reader_read_color(struct dao_oni_reader *reader, uint32_t stream,
				      uint32_t frame, struct dao_frame *out,
				      struct dao_error *err);

/*
 * The frame of stream `other` recorded nearest in time to frame `frame` of
 * stream `stream` (the earlier one on a tie).  OpenNI2's player pushes each
 * stream's frames at their recorded times, so a reader taking a depth frame
 * and the colour frame at hand gets the one recorded last before it; the
 * nearest one is the same frame when colour leads depth by less than half a
 * frame (the Kinect recording in the tests: 11.7 of 33.3 ms, colour N with
 * depth N), and the closer one when it does not.
 * -EINVAL for bad arguments, -ENOENT if `other` has no frames.
 */
DAO_API int dao_oni_reader_match_frame(const struct dao_oni_reader *reader, uint32_t stream,
				       uint32_t frame, uint32_t other, uint32_t *match);

/* --- writing ---------------------------------------------------------- */

/* What dao_oni_writer_open() records: the depth stream's layout and codec.  Begins
 * with `size` (docs/abi.md): start from DAO_ONI_WRITER_OPTIONS_INIT. */
struct dao_oni_writer_options {
	uint32_t size;              /* sizeof, DAO_ONI_WRITER_OPTIONS_INIT */
	/* size of the depth images, pixels */
	uint32_t width, height;
	uint32_t fps;               /* nominal frame rate (1..1000) */
	enum dao_oni_codec codec;   /* NONE, 16Z or 16ZT */
	int pixel_format;           /* DAO_ONI_PIXEL_DEPTH_1_MM or _100_UM */
	uint32_t max_depth;         /* xnDeviceMaxDepth in counts; 0 = 10 m in the unit */
	double hfov, vfov;          /* radians, in (0, pi) */
	int mirrored;               /* recorded as xnMirror */
	int overwrite;              /* replace a file already at path (else -EEXIST) */
};

/* Options with their size set and everything else 0 (the fields say which 0 is a
 * default: max_depth); width, height, fps, codec, pixel_format, hfov and vfov
 * must be given. */
#define DAO_ONI_WRITER_OPTIONS_INIT { .size = sizeof(struct dao_oni_writer_options) }

struct dao_oni_writer;

/* Frames reach the disk (fdatasync) at most this long after they were written. */
#define DAO_ONI_SYNC_INTERVAL_MS 1000

/*
 * Starts a recording with one depth node, at `path` itself: the file grows
 * there frame by frame (no temporary name), so whatever happens to the
 * process, the file holds every frame write_depth accepted, and
 * dao_oni_reader_open recovers it up to the last complete frame.  The file
 * is synced (fdatasync) when a frame is written DAO_ONI_SYNC_INTERVAL_MS or
 * more after the last sync (dao_oni_writer_sync for idle times), and the
 * synced frame count and timestamps are then written into the header, so
 * that OpenNI2 too plays an unfinished file up to its last sync.
 * A file already at `path` is left alone (-EEXIST) unless opts->overwrite;
 * only regular files are written (-EINVAL for devices, FIFOs, directories).
 * opts->size must be set (DAO_ONI_WRITER_OPTIONS_INIT): -EINVAL with a
 * message when it is smaller than the first layout or larger than this
 * library's struct (a newer program's options it cannot honour).
 */
DAO_API int dao_oni_writer_open(const char *path, const struct dao_oni_writer_options *opts,
				struct dao_oni_writer **out, struct dao_error *err);

/*
 * Appends a depth frame (DAO_PIXFMT_DEPTH16 of the declared size; counts are
 * converted when its depth_unit differs from the file's) with a timestamp in
 * microseconds, which must not go backwards.  Counts above max_depth are
 * -ERANGE; so are values the chosen codec cannot represent (16z: >= 32768;
 * 16zT: more than 32768 distinct values in one frame).  0 means the frame
 * is in the file (handed to the kernel).  A failed write (-ENOSPC on a full
 * disk, also for a short write; -EDQUOT, -EFBIG, -EIO, ...) or sync ends
 * the recording: the partial record is cut off again where possible, the
 * frames before it stay, and every later write returns the same error.
 */
DAO_API int dao_oni_writer_write_depth(struct dao_oni_writer *writer,
				       const struct dao_frame *depth, uint64_t timestamp_us,
				       struct dao_error *err);

/* Syncs now (fdatasync, then the synced frame count into the header). */
DAO_API int dao_oni_writer_sync(struct dao_oni_writer *writer, struct dao_error *err);

/* How far a recording got: frames written, synced, and the error that ended it.
 * Filled by the library: `size` first, fields appended (docs/abi.md). */
struct dao_oni_writer_status {
	uint32_t size;              /* bytes filled, set by the library */
	uint32_t frames;            /* in the file: write_depth returned 0 */
	uint32_t synced_frames;     /* of those, synced and counted in the header */
	uint32_t syncs;             /* fdatasync calls so far */
	int error;                  /* the error that ended the recording, 0 if none */
	uint64_t bytes;             /* up to the end of the last complete record */
};

/* A struct dao_oni_writer_status with its size set and every field 0. */
#define DAO_ONI_WRITER_STATUS_INIT { .size = sizeof(struct dao_oni_writer_status) }

/*
 * Copies the writer's status into `status`, a struct of `size` bytes: the
 * fields that fit, nothing past them, and status->size (all 0 for a NULL
 * writer).  -EINVAL if status is NULL or `size` cannot hold `size`.
 * Programs call dao_oni_writer_get_status(); bindings pass their size.
 */
DAO_API int dao_oni_writer_get_status_sized(const struct dao_oni_writer *writer,
					    struct dao_oni_writer_status *status, size_t size);

/* Fills `status` with the writer's state (dao_oni_writer_get_status_sized()). */
static inline void dao_oni_writer_get_status(const struct dao_oni_writer *writer,
					     struct dao_oni_writer_status *status)
{
	(void)dao_oni_writer_get_status_sized(writer, status, sizeof(*status));
}

/*
 * Finalises the file: seek table and end record after the last complete
 * frame, frame count and timestamps in the header, synced.  After a failed
 * write too (the frames before the failure are finalised; that is 0 when it
 * worked).  If even the end record does not fit (the disk is still full),
 * the file keeps its frames unfinalised, with the header counting all of
 * them, and the error says so.  A recording without frames is removed
 * (-EINVAL).  Frees the writer whatever the outcome.
 */
DAO_API int dao_oni_writer_finish(struct dao_oni_writer *writer, struct dao_error *err);

/*
 * Stops without finalising and frees the writer: the frames written stay in
 * an unfinished file (the reader recovers it); a file without frames is
 * removed.
 */
DAO_API void dao_oni_writer_abort(struct dao_oni_writer *writer);

/* "none", "16z", "16zt", ... and back (case-insensitive); -EINVAL if unknown. */
DAO_API const char *dao_oni_codec_name(enum dao_oni_codec codec);
/* The codec called `name`: 0, or -EINVAL if unknown. */
DAO_API int dao_oni_codec_from_name(const char *name, enum dao_oni_codec *codec);

#ifdef __cplusplus
}
#endif
#endif
