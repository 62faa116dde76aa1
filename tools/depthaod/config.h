/* SPDX-License-Identifier: MIT */
/*
 * depthaod configuration: an INI file (ini_file.h) with [source], [ao],
 * [sink.NAME]... and [daemon]; command-line options override it.  Every key
 * is checked: unknown keys and bad values are errors naming file:line and key.
 */
#ifndef DAOD_CONFIG_H
#define DAOD_CONFIG_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#define DAOD_MAX_SINKS 16
#define DAOD_MAX_URI 4096        /* a path of PATH_MAX and a plugin prefix fit */
#define DAOD_MAX_AO_KEYS 64

/* What a sink receives. */
enum stream_kind {
	STREAM_SHADED = 0, /* RGB24: occlusion-shaded */
	STREAM_AO,         /* GRAY16: round(visibility x 65535) */
	STREAM_AO8,        /* GRAY8: round(visibility x 255) */
	STREAM_DEPTH,      /* DEPTH16: the input depth (recorders) */
	STREAM_OVERLAY,    /* RGB24: the source's colour x AO (colour sources only) */
	STREAM_FILTERED_DEPTH, /* DEPTH16: the filtered depth, in the input's unit */
	STREAM_COUNT,
};

const char *stream_name(enum stream_kind k);

struct sink_config {
	char name[64];
	char uri[DAOD_MAX_URI];
	enum stream_kind stream;
	unsigned queue;          /* frames buffered for this sink (1..64) */
};

struct ao_setting {
	char key[64], value[128];
};

struct daemon_config {
	char path[512];          /* the config file ("" if none), for messages and reload */

	/* [source] */
	char source_uri[DAOD_MAX_URI];
	enum dao_playback playback;
	int loop;
	uint32_t start;
	float depth_unit;        /* PNG sources; 0 = the source's default */
	int has_intrinsics;
	double intrinsics[4];    /* fx, fy, cx, cy */
	int has_fov;
	double fov_deg[2];
	/* intrinsics_file: an Open3D JSON or ROS CameraInfo YAML, read when the key is set */
	int has_intrinsics_file;
	char intrinsics_file[512];
	uint32_t file_width, file_height; /* the size the file is for */
	double file_intrinsics[4];        /* fx, fy, cx, cy */
	char camera_warning[640];         /* from the file (distortion), logged at start */
	unsigned retry_initial_ms, retry_max_ms;
	unsigned input_queue;
	uint64_t max_pixels;     /* largest depth image decoded from files (0 = the default) */

	/* [ao]: applied in order over the preset (quality first, wherever it is) */
	enum dao_quality quality;
	struct ao_setting ao[DAOD_MAX_AO_KEYS];
	unsigned nao;

	/* [sink.NAME] */
	struct sink_config sinks[DAOD_MAX_SINKS];
	unsigned nsinks;

	/* [daemon] */
	char socket_path[108];
	char socket_group[64];   /* who else may use the socket ("" = "depthao" if it exists) */
	unsigned socket_idle_timeout_s; /* a control connection idle this long is closed */
	unsigned stats_interval_s;
	char stats_json[DAOD_MAX_URI];
	int log_level;           /* enum log_level */
	int drain_on_stop;
	uint64_t max_frames;     /* stop after this many processed frames (0 = never) */
};

void config_defaults(struct daemon_config *c);

/*
 * Reads `path` into `c` (over what is there).  Returns 0, or -1 with msg
 * "PATH:LINE: [section] key: what is wrong" (the first error).
 */
int config_load(struct daemon_config *c, const char *path, char *msg, size_t len);

/* One setting, from the file or the command line (`where` prefixes errors). */
int config_set(struct daemon_config *c, const char *section, const char *key, const char *value,
	       char *msg, size_t len);

/* Checks the whole: a source, at least one sink, the [ao] set valid together. */
int config_check(const struct daemon_config *c, char *msg, size_t len);

/* The AO parameters the config describes. */
int config_params(const struct daemon_config *c, struct dao_params *out, char *msg, size_t len);

#endif
