/* SPDX-License-Identifier: MIT */
/* Part of libdepthao-io (pkg-config depthao-io, <depthao/io.h>), not of the AO core libdepthao. */
/*
 * Sources and sinks: the plugin interface.
 *
 * A plugin is a shared module exporting one function,
 *     const struct dao_plugin *dao_plugin_entry(void);
 * that returns a static table: the ABI version it was built against, the
 * table's size and version (DAO_PLUGIN_HEADER fills the three), its name,
 * and a source and/or a sink vtable.  Modules are looked up in the
 * directories of $DEPTHAO_PLUGIN_PATH (colon-separated; for tests and
 * development), then in the install directory; the first module with a
 * given name wins.  Sources that need no extra dependency are built into
 * the library: sources "oni" (.oni recordings through depthao's own reader),
 * "bag" (ROS 1 bags and RealSense .bag recordings, FILE.bag[?topic=T][&unit=M])
 * and "images" (a 16-bit depth PNG or a directory of them, in name order);
 * sinks "images" (numbered PNGs), "y4m" (YUV4MPEG2 to a file, FIFO or
 * stdout) and "oni" (the .oni recorder).
 *
 * A source is opened from a URI "NAME:REST" (plugin NAME gets REST) or, with
 * no known prefix, by asking every source how well it handles the URI
 * (probe) and taking the best.  All calls return 0 or a negative errno code:
 *   read:  0 = a frame, -EAGAIN = no frame within the timeout,
 *          -ENODEV = the device is gone (unplugged), DAO_SOURCE_EOS (> 0)
 *          = the end of a recording (not an error), other < 0 = errors;
 *          a recording's frame that cannot be decoded is skipped (the next
 *          read delivers the one after it).
 * Frames from read stay valid until release (or the next read); sources own
 * their buffers.  One thread at a time per source; separate sources are
 * independent.
 *
 * Growing the interface without breaking built plugins and programs (README
 * "ABI policy"; PipeWire versions its interfaces the same way):
 *  - struct dao_source_info, dao_source_options, dao_sink_format,
 *    dao_sink_host and dao_sink_frame_info begin with `size`, the sizeof of the struct as the code
 *    that filled it was built.  Fields are only ever appended.  Whoever reads
 *    a field added after the first layout checks DAO_STRUCT_HAS() first (and
 *    takes 0 / the default otherwise); whoever fills a struct the other side
 *    allocated writes such a field only when DAO_STRUCT_HAS() says it is there.
 *    The fields below without a "since" note are in every layout.
 *  - struct dao_source_ops and dao_sink_ops begin with `version`
 *    (DAO_SOURCE_OPS_VERSION, DAO_SINK_OPS_VERSION as the plugin was built).
 *    A callback added later says "since version N"; the host calls it only
 *    when version >= N, and loads plugins built for newer versions than its
 *    own (it uses what it knows).
 *  - struct dao_plugin, the descriptor, begins with abi_version, `size` and
 *    `version` (DAO_PLUGIN_HEADER; DAO_PLUGIN_VERSION as the plugin was
 *    built); fields are appended to it as to the structs above.  The loader
 *    refuses, with a message saying what to do, a descriptor smaller than
 *    the first one that carried a size, or of a version it does not know
 *    (0, or newer than this library's DAO_PLUGIN_VERSION).
 *  - The callbacks of struct dao_source_ops and dao_sink_ops not marked
 *    optional below are required: the loader refuses, naming the module and
 *    the callback, a source without open, get_info, start, read or close and
 *    a sink without open, negotiate, write or close.
 *  - DAO_PLUGIN_ABI_VERSION changes only when the layout breaks; a plugin
 *    built for another one is refused with a message.
 */
#ifndef DEPTHAO_PLUGIN_H
#define DEPTHAO_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>
#include <depthao/frame.h>
#include <depthao/uri.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* 2: the structs carry `size` and the ops tables `version`; 3 (depthao 1.0):
 * the descriptor struct dao_plugin carries `size` and `version` too (plugins
 * built for 1 or 2 are refused: rebuild them) */
#define DAO_PLUGIN_ABI_VERSION 3
/* The descriptor's own version: 1 is the first layout with `size` (ABI 3). */
#define DAO_PLUGIN_VERSION 1
/* The layout of struct dao_source_ops this header describes (2: frame_pose). */
#define DAO_SOURCE_OPS_VERSION 2
/* The layout of struct dao_sink_ops this header describes. */
#define DAO_SINK_OPS_VERSION 1
/* The symbol a plugin module exports (DAO_PLUGIN_DEFINE). */
#define DAO_PLUGIN_ENTRY_SYMBOL "dao_plugin_entry"
/* The environment variable with the plugin directories. */
#define DAO_PLUGIN_PATH_ENV "DEPTHAO_PLUGIN_PATH"

/* read(): the end of a recording (files without looping). */
#define DAO_SOURCE_EOS 1

/* The struct at `ptr` (of `type`, with its `size` set) holds `field`. */
#define DAO_STRUCT_HAS(type, ptr, field) \
	((size_t)(ptr)->size >= offsetof(type, field) + sizeof(((type *)0)->field))

/* What a source delivers: the depth stream, the camera, colour. */
struct dao_source_info {
	uint32_t size;              /* sizeof, set by whoever allocated it */
	uint32_t width, height;     /* depth image size */
	enum dao_pixfmt format;     /* DAO_PIXFMT_DEPTH16 or DAO_PIXFMT_DEPTH_F32 */
	float depth_unit;           /* metres per count (DEPTH16) */
	int has_fov;                /* the source knows its field of view */
	double hfov, vfov;          /* radians */
	double fps;                 /* nominal, 0 if unknown */
	int64_t frame_count;        /* frames in a recording, -1 for live sources */
	int live;                   /* a device (frames are dropped if not read in time) */
	int mirrored;               /* images are mirrored left-right */
	int registered;             /* depth is registered to the colour camera */
	int has_color;              /* read() also delivers colour (RGB24) */
	/* size of the colour frames, when has_color */
	uint32_t color_width, color_height;
	char description[160];      /* one line for logs: device or file, format, codec */
	char warning[256];          /* empty, or a line to show as a warning (e.g. a
				       recording recovered after its writer crashed) */
	int has_intrinsics;         /* fx, fy, cx, cy are known (a ROS CameraInfo); they
				       describe the camera better than hfov/vfov */
	double fx, fy, cx, cy;      /* pixels */
};

/* How a recording is played; live sources ignore what does not apply. */
enum dao_playback {
	DAO_PLAYBACK_MANUAL = 0,    /* every frame once, as fast as the caller reads */
	DAO_PLAYBACK_REALTIME,      /* paced by the recorded timestamps */
};

/* How a source is opened (dao_source_open()). */
struct dao_source_options {
	uint32_t size;              /* sizeof: DAO_SOURCE_OPTIONS_INIT */
	/* how a recording is played */
	enum dao_playback playback;
	int loop;                   /* at the end, start again (at start_frame) instead of
				       DAO_SOURCE_EOS */
	uint32_t start_frame;       /* first frame delivered, 0-based */
	uint32_t step;              /* deliver every step-th frame (0 or 1 = all) */
	int want_color;             /* also deliver colour when the source has it */
	float depth_unit;           /* metres per count where the files do not say
				       (16-bit PNG images); 0 = 0.001 */
};

/* Options with their size set and everything else 0 (the defaults). */
#define DAO_SOURCE_OPTIONS_INIT { .size = sizeof(struct dao_source_options) }

/* A frame from a source: depth, colour when asked for, its position. */
struct dao_source_frame {
	struct dao_frame depth;     /* sequence = recorded/device frame number */
	struct dao_frame color;     /* format DAO_PIXFMT_NONE when absent */
	uint64_t index;             /* 0-based position in a recording; count for live */
};

/*
 * The camera's pose for one frame, from what the source carries (a ROS
 * recording's tf or odometry): dao_source_frame_pose().  Filled by the
 * library up to the caller's size (docs/abi.md).
 */
struct dao_source_pose {
	uint32_t size;              /* sizeof: DAO_SOURCE_POSE_INIT */
	uint32_t reserved;          /* 0 */
	/* the rotation from the depth image's frame (its header.frame_id, an optical
	 * frame: x right, y down, z forward) to the fixed frame: a unit quaternion x,
	 * y, z, w, as dao_context_set_pose() takes it */
	double rotation[4];
	double translation[3];      /* the optical centre in the fixed frame, metres */
	/* one line: the frames and where the poses come from, e.g. "'camera_depth_optical_frame'
	 * in 'odom' from /tf, /tf_static (1200 transforms)" */
	char description[160];
	/* empty, or a line to show once (set with the first pose only): transforms
	 * skipped as malformed, the odometry's frame taken for the camera's */
	char warning[256];
};

/* A pose with its size set and everything else 0. */
#define DAO_SOURCE_POSE_INIT { .size = sizeof(struct dao_source_pose) }

/* One entry of a device listing. */
struct dao_device_entry {
	char uri[256];              /* what to pass to open (without the plugin prefix) */
	char name[128];             /* vendor and model */
	char detail[128];           /* e.g. USB ids, modes */
};

/* Called once per device by a source's list_devices. */
typedef void (*dao_device_cb)(void *user, const struct dao_device_entry *entry);

/* A source plugin's table: open a URI, report the stream, read frames. */
struct dao_source_ops {
	uint32_t version;           /* DAO_SOURCE_OPS_VERSION */
	/* optional: 0..100, how well this source handles `uri` (auto selection), 0 = not at
	 * all (NULL: never picked for a URI that names no plugin) */
	int (*probe)(const char *uri);
	/* optional: enumerate devices; returns the count or < 0 */
	int (*list_devices)(dao_device_cb cb, void *user, struct dao_error *err);
	/* opens `uri` (without the plugin prefix); its state in *state */
	int (*open)(const char *uri, const struct dao_source_options *opts, void **state,
		    struct dao_error *err);
	/* fills `info` (its size set by the host; DAO_STRUCT_HAS for later fields) */
	void (*get_info)(void *state, struct dao_source_info *info);
	/* starts streaming */
	int (*start)(void *state, struct dao_error *err);
	/* the next frame: 0, -EAGAIN, -ENODEV, DAO_SOURCE_EOS or an error */
	int (*read)(void *state, struct dao_source_frame *frame, int timeout_ms,
		    struct dao_error *err);
	/* optional: gives a frame from read back */
	void (*release)(void *state, struct dao_source_frame *frame);
	/* optional: the next read delivers frame `index` of a recording */
	int (*seek)(void *state, uint64_t index, struct dao_error *err);
	/* optional: after the last read, before close (a source that was started) */
	void (*stop)(void *state);
	/* frees the state */
	void (*close)(void *state);
	/*
	 * since version 2, optional: the camera's pose for `frame`, the frame
	 * the last read delivered (before its release), into `pose` (its size
	 * set by the host; DAO_STRUCT_HAS for later fields).  0; -ENOENT: this
	 * frame has none (a gap in the poses), the message says why; -ENOTSUP:
	 * the source carries no poses; other < 0: it cannot give any (the
	 * message says what is wrong and what to do), every call the same.
	 */
	int (*frame_pose)(void *state, const struct dao_source_frame *frame,
			  struct dao_source_pose *pose, struct dao_error *err);
};

/* The format a sink negotiates (dao_sink_negotiate()). */
struct dao_sink_format {
	uint32_t size;              /* sizeof: DAO_SINK_FORMAT_INIT */
	enum dao_pixfmt format;     /* GRAY8, GRAY16, RGB24 or DEPTH16 */
	/* size in pixels */
	uint32_t width, height;
	double fps;                 /* nominal, 0 if unknown */
	float depth_unit;           /* DEPTH16: metres per count */
	int has_fov;                /* the camera's field of view is known */
	double hfov, vfov;          /* radians (recorders store it) */
	int mirrored;               /* the images are mirrored left-right (recorders store it) */
	uint32_t reserved;          /* 0; the struct has no tail padding a later field could
				       fall into (tests/plugin/test_abi_growth.c) */
};

/* A format with its size set and everything else 0. */
#define DAO_SINK_FORMAT_INIT { .size = sizeof(struct dao_sink_format) }

/*
 * The streams a host (depthaod) produces for every frame, for sinks that take
 * more than the one they were configured for (write_stream, want_streams).
 */
enum dao_stream {
	DAO_STREAM_SHADED = 0,      /* RGB24: occlusion-shaded */
	DAO_STREAM_AO,              /* GRAY16: visibility x 65535 */
	DAO_STREAM_AO8,             /* GRAY8: visibility x 255 */
	DAO_STREAM_DEPTH,           /* DEPTH16: the input depth */
	DAO_STREAM_OVERLAY,         /* RGB24: the source's colour x AO (colour sources only) */
	DAO_STREAM_FILTERED_DEPTH,  /* DEPTH16: the filtered depth (dao_context_get_depth) in
				       the input's unit (float-metre input: millimetres) */
	DAO_STREAM_COUNT,
};

/* What write_stream gets with each frame (from the host: a plugin reads a
 * field added after the first layout only when DAO_STRUCT_HAS() says so). */
struct dao_sink_frame_info {
	uint32_t size;              /* sizeof, set by the host */
	enum dao_stream stream;     /* which of the frame's streams this is */
	uint64_t capture_ns;        /* CLOCK_MONOTONIC when the source delivered the frame
				       (latency = now - capture_ns), 0 if unknown */
	/* appended after the first layout (read them when DAO_STRUCT_HAS(struct
	 * dao_sink_frame_info, info, pose_translation)): the camera's pose at this
	 * frame where the pipeline follows the camera (the temporal depth filter on,
	 * depth-temporal-motion icp, source or source+icp): has_pose 1,
	 * pose_rotation the unit quaternion x, y, z, w (w last) of the rotation from
	 * the frame's optical frame (x right, y down, z forward) to the first
	 * followed frame's, pose_translation the optical centre there, metres:
	 * x_first = R x + t, the motions accepted since that frame composed
	 * (depthaod's stats "motion", depthao process --pose-out).  has_pose 0: no
	 * pose (the motion not followed; a frame after a cut or a gap in the
	 * source's poses, whose motion is unknown; one whose estimate was refused;
	 * a host that does not track it). */
	int32_t has_pose;
	uint32_t reserved;          /* 0 */
	double pose_rotation[4];    /* x, y, z, w: optical frame to the first one's */
	double pose_translation[3]; /* the optical centre in the first one's, m */
};

/* Levels of the messages a sink logs through its host. */
enum dao_log_level { DAO_LOG_ERROR = 0, DAO_LOG_WARN, DAO_LOG_INFO };

/* What a sink may ask of the program running it (the daemon); all optional. */
struct dao_sink_host {
	uint32_t size;              /* sizeof: DAO_SINK_HOST_INIT */
	/* passed back to every callback */
	void *user;
	/* an AO parameter of the running pipeline, as text (dao_params_get); 0 or < 0 */
	int (*get_param)(void *user, const char *name, char *value, size_t len);
	/* changes one for the next frames (dao_params_set rules); 0 or < 0 */
	int (*set_param)(void *user, const char *name, const char *value);
	/* one line for the log (e.g. the file a recorder chose because the one named
	 * existed); `level` is an enum dao_log_level */
	void (*log)(void *user, int level, const char *message);
	/*
	 * Sets several parameters at once, all or none: each is checked as set_param
	 * does and the whole set is validated before anything changes.  0, or < 0 with
	 * the reason in msg (the parameter, the value, the valid range).
	 */
	int (*set_params)(void *user, const char *const *names, const char *const *values,
			  size_t count, char *msg, size_t len);
	/* The host's statistics as one JSON object in json; its length, or < 0
	 * (-ENOSPC: json too small) */
	int (*stats_json)(void *user, char *json, size_t len);
	/*
	 * Asks for these streams (a mask of 1u << enum dao_stream) besides the one the
	 * sink was configured for, from the next frame on, until asked again (0 = none).
	 * They arrive through write_stream only, in any format, never negotiated.
	 * The overlay exists only for sources with colour.  0 or < 0.
	 */
	int (*want_streams)(void *user, unsigned mask);
};

/* A host with its size set and no callbacks. */
#define DAO_SINK_HOST_INIT { .size = sizeof(struct dao_sink_host) }

/* A sink plugin's table: open a URI, negotiate a format, write frames. */
struct dao_sink_ops {
	uint32_t version;           /* DAO_SINK_OPS_VERSION */
	/* optional: 0..100, how well this sink handles `uri` (auto selection), 0 = not at all
	 * (NULL: never picked for a URI that names no plugin) */
	int (*probe)(const char *uri);
	/* opens `uri` (without the plugin prefix); its state in *state */
	int (*open)(const char *uri, void **state, struct dao_error *err);
	/*
	 * Called before the first write (again, until then, to try another
	 * stream): accept `fmt`, or change fmt->format to the nearest format
	 * the sink takes and return 0 (writes must then have that format; the
	 * caller converts or picks another stream), or -ENOTSUP.
	 */
	int (*negotiate)(void *state, struct dao_sink_format *fmt, struct dao_error *err);
	/*
	 * frame->sequence numbers the output where a sink names files by frame.
	 * 0: the frame is in the output (handed to the kernel, for files).
	 * -ECANCELED: the sink is finished for good (e.g. its window was closed).
	 * -ENOSPC (also for a short write on a full disk), -EDQUOT, -EFBIG,
	 * -EROFS, -EPIPE (the reader went away): the output cannot take more;
	 * everything written before stays (a recorder's file keeps its complete
	 * frames), and later writes fail the same way.
	 */
	int (*write)(void *state, const struct dao_frame *frame, struct dao_error *err);
	/* optional (NULL: nothing buffered): hands on anything buffered; recorders
	 * also sync their file to disk */
	int (*flush)(void *state, struct dao_error *err);
	/* finalises (headers, seek tables, renames) and frees; errors say what was lost;
	 * never removes what was written */
	int (*close)(void *state, struct dao_error *err);
	/* optional: the host, before negotiate; valid until close (e.g. window controls) */
	void (*attach_host)(void *state, const struct dao_sink_host *host);
	/*
	 * optional: takes every frame in place of write, with the stream it belongs to
	 * and its capture time: frames of the configured stream (negotiated, as for
	 * write) and those of the streams asked for with want_streams (any format;
	 * the sink checks).  Same return values as write.
	 */
	int (*write_stream)(void *state, const struct dao_sink_frame_info *info,
			    const struct dao_frame *frame, struct dao_error *err);
};

/* What a plugin module returns from dao_plugin_entry(). */
struct dao_plugin {
	uint32_t abi_version;       /* DAO_PLUGIN_ABI_VERSION (at offset 0 in every ABI) */
	uint32_t size;              /* sizeof(struct dao_plugin) as the plugin was built */
	uint32_t version;           /* DAO_PLUGIN_VERSION as the plugin was built */
	const char *name;           /* lower case, the URI prefix: "openni2" */
	/* one line for `depthao devices` */
	const char *description;
	const struct dao_source_ops *source; /* NULL if not a source */
	const struct dao_sink_ops *sink;     /* NULL if not a sink */
};

/*
 * The first fields of every descriptor, in a designated initialiser:
 *     static const struct dao_plugin my_plugin = {
 *             DAO_PLUGIN_HEADER,
 *             .name = "mine",
 *             ...
 *     };
 */
#define DAO_PLUGIN_HEADER                                                       \
	.abi_version = DAO_PLUGIN_ABI_VERSION, .size = sizeof(struct dao_plugin), \
	.version = DAO_PLUGIN_VERSION

/* The type of dao_plugin_entry(). */
typedef const struct dao_plugin *(*dao_plugin_entry_fn)(void);

/*
 * A module's entry point, returning `plugin` (its static struct dao_plugin),
 * exported whatever the module's default visibility.  In one C file:
 *     DAO_PLUGIN_DEFINE(my_plugin)
 */
#define DAO_PLUGIN_DEFINE(plugin)                                                        \
	__attribute__((visibility("default"))) const struct dao_plugin *dao_plugin_entry(void); \
	const struct dao_plugin *dao_plugin_entry(void)                                  \
	{                                                                                \
		return &(plugin);                                                        \
	}

/* --- the registry ------------------------------------------------------ */

struct dao_plugins;

/*
 * Loads the built-in plugins and every module found in `path` (a
 * colon-separated list of directories; NULL = $DEPTHAO_PLUGIN_PATH, then the
 * install directory).  Modules that fail to load (a missing library, a wrong
 * ABI version) are skipped and listed by dao_plugins_skipped().  An empty
 * `path` ("") loads the built-in plugins only.
 */
DAO_API int dao_plugins_load(struct dao_plugins **out, const char *path, struct dao_error *err);
/* Unloads the modules and frees the registry; NULL-safe. */
DAO_API void dao_plugins_free(struct dao_plugins *plugins);
/* The number of plugins loaded. */
DAO_API size_t dao_plugins_count(const struct dao_plugins *plugins);
/* Plugin i (< dao_plugins_count()). */
DAO_API const struct dao_plugin *dao_plugins_get(const struct dao_plugins *plugins, size_t i);
/* Where plugin i came from: a module path, or "built-in". */
DAO_API const char *dao_plugins_origin(const struct dao_plugins *plugins, size_t i);
/* The plugin called `name`, or NULL. */
DAO_API const struct dao_plugin *dao_plugins_find(const struct dao_plugins *plugins,
						  const char *name);
/* Modules that were found but not loaded: "path: reason", i < count. */
DAO_API size_t dao_plugins_skipped_count(const struct dao_plugins *plugins);
/* Skipped module i: "path: reason". */
DAO_API const char *dao_plugins_skipped(const struct dao_plugins *plugins, size_t i);
/* The compiled-in module directory. */
DAO_API const char *dao_plugins_install_dir(void);

/* dao_uri_prefix_len(), how dao_source_open() and dao_sink_open() split a URI, and the
 * option parser of every plugin: <depthao/uri.h>. */

/* --- sources ----------------------------------------------------------- */

struct dao_source;

/*
 * Opens a source.  `uri` is "NAME:REST" for plugin NAME, or anything else to
 * pick the source that probes best (a path ending in .oni -> "oni", .bag ->
 * "bag").
 * Unknown plugin names are -ENOENT with the list of available sources.
 * `opts` may be NULL (the defaults); else its size must be set
 * (DAO_SOURCE_OPTIONS_INIT), -EINVAL otherwise.
 */
DAO_API int dao_source_open(const struct dao_plugins *plugins, const char *uri,
			    const struct dao_source_options *opts, struct dao_source **out,
			    struct dao_error *err);
/*
 * dao_source_open() with a limit on the size of the depth images,
 * width x height (0 = DAO_DEFAULT_MAX_PIXELS, what dao_source_open() uses).
 * The built-in sources check what a file declares before they allocate
 * anything of its size; for plugin sources the size they report after
 * open is checked.  -EFBIG with a message when the source is larger.
 */
DAO_API int dao_source_open_limited(const struct dao_plugins *plugins, const char *uri,
				    const struct dao_source_options *opts, uint64_t max_pixels,
				    struct dao_source **out, struct dao_error *err);
/* The plugin behind a source. */
DAO_API const struct dao_plugin *dao_source_plugin(const struct dao_source *src);
/*
 * Fills `info`, a struct dao_source_info of `size` bytes (the fields that
 * fit; the rest of what a source does not know is 0) and sets info->size.
 * -EINVAL if `size` is smaller than the first struct that carried a size.
 * Programs call dao_source_get_info(); bindings pass their struct's size.
 */
DAO_API int dao_source_get_info_sized(const struct dao_source *src, struct dao_source_info *info,
				      size_t size);
/* dao_source_get_info_sized() with the caller's sizeof. */
static inline void dao_source_get_info(const struct dao_source *src,
				       struct dao_source_info *info)
{
	(void)dao_source_get_info_sized(src, info, sizeof(*info));
}
/* Starts streaming (before the first read). */
DAO_API int dao_source_start(struct dao_source *src, struct dao_error *err);
/* The next frame: 0, -EAGAIN (none within timeout_ms), -ENODEV (device gone), DAO_SOURCE_EOS, or an error. */
DAO_API int dao_source_read(struct dao_source *src, struct dao_source_frame *frame,
			    int timeout_ms, struct dao_error *err);
/* Gives a frame from dao_source_read() back. */
DAO_API void dao_source_release(struct dao_source *src, struct dao_source_frame *frame);
/* -ENOTSUP for sources that cannot seek (live devices). */
DAO_API int dao_source_seek(struct dao_source *src, uint64_t index, struct dao_error *err);
/*
 * The camera's pose for `frame`, the frame dao_source_read() last
 * delivered (before dao_source_release()), into `pose` of `size` bytes
 * (filled up to min(size, the library's sizeof); pose->size set to that).
 * The built-in "bag", "mcap" and "db3" sources take it from the
 * recording's tf or odometry (docs/sources.md, "Camera poses"): their
 * first call reads the recording's transforms (it may take a while on a
 * large recording).  0; -ENOENT: this frame has no pose (a gap, a time
 * outside the transforms), the message says why; -ENOTSUP: the source
 * carries no poses (other sources, plugins built before ops version 2);
 * other < 0: the poses cannot be had (no tf topic, the depth frame not
 * connected, ...), every call the same, with what to do in the message.
 */
DAO_API int dao_source_frame_pose_sized(struct dao_source *src,
					const struct dao_source_frame *frame,
					struct dao_source_pose *pose, size_t size,
					struct dao_error *err);
/* dao_source_frame_pose_sized() with the size of this header's struct. */
static inline int dao_source_frame_pose(struct dao_source *src,
					const struct dao_source_frame *frame,
					struct dao_source_pose *pose, struct dao_error *err)
{
	return dao_source_frame_pose_sized(src, frame, pose, sizeof(*pose), err);
}
/* Stops (if started) and closes; NULL-safe. */
DAO_API void dao_source_close(struct dao_source *src);

/* --- sinks ------------------------------------------------------------- */

struct dao_sink;

/*
 * Opens a sink: "NAME:REST" for plugin NAME, else the sink that probes best.
 * -ENOTSUP from a sink's open means it cannot work here at all (e.g. a
 * window without a display): callers should not retry it.
 */
DAO_API int dao_sink_open(const struct dao_plugins *plugins, const char *uri,
			  struct dao_sink **out, struct dao_error *err);
/* The plugin behind a sink. */
DAO_API const struct dao_plugin *dao_sink_plugin(const struct dao_sink *sink);
/* Passes the host to sinks that take one (no-op otherwise); before negotiate.
 * host->size must be set (DAO_SINK_HOST_INIT); the sink gets a copy. */
DAO_API void dao_sink_attach_host(struct dao_sink *sink, const struct dao_sink_host *host);
/* fmt->size must be set (DAO_SINK_FORMAT_INIT); -EINVAL otherwise. */
DAO_API int dao_sink_negotiate(struct dao_sink *sink, struct dao_sink_format *fmt,
			       struct dao_error *err);
/* The frame must have the negotiated format and size (-EINVAL otherwise). */
DAO_API int dao_sink_write(struct dao_sink *sink, const struct dao_frame *frame,
			   struct dao_error *err);
/* Hands on what the sink buffered (recorders sync their file); 0 or < 0. */
DAO_API int dao_sink_flush(struct dao_sink *sink, struct dao_error *err);
/*
 * A frame with its stream and capture time: to the sink's write_stream when it
 * has one (frames of other streams than the negotiated one are then passed
 * whatever their format), else to write (frames of the negotiated stream only;
 * others are -ENOTSUP).
 */
DAO_API int dao_sink_write_stream(struct dao_sink *sink, const struct dao_sink_frame_info *info,
				  const struct dao_frame *frame, struct dao_error *err);
/* 1 if the sink takes frames of several streams (it has write_stream). */
DAO_API int dao_sink_takes_streams(const struct dao_sink *sink);
/* Finalises and frees; NULL-safe (returns 0). */
DAO_API int dao_sink_close(struct dao_sink *sink, struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
