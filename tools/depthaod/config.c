/* SPDX-License-Identifier: MIT */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <depthao/output_file.h>

#include "common/camera_file.h"
#include "common/pixel_limit.h"
#include "ini_file.h"
#include "log.h"

static const char *const stream_names[STREAM_COUNT] = {"shaded", "ao", "ao8", "depth", "overlay",
								"filtered-depth"};

const char *stream_name(enum stream_kind k)
{
	return k < STREAM_COUNT ? stream_names[k] : "?";
}

void config_defaults(struct daemon_config *c)
{
	memset(c, 0, sizeof(*c));
	c->playback = DAO_PLAYBACK_REALTIME;
	c->retry_initial_ms = 500;
	c->retry_max_ms = 10000;
	c->input_queue = 4;
	c->quality = DAO_QUALITY_DEFAULT;
	c->stats_interval_s = 10;
	c->socket_idle_timeout_s = 30;
	c->log_level = LOG_INFO;
	c->drain_on_stop = 1;
}

__attribute__((format(printf, 3, 4))) static int fail(char *msg, size_t len, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, len, fmt, ap);
	va_end(ap);
	return -1;
}

static int parse_bool(const char *v, int *out)
{
	if (!strcasecmp(v, "true") || !strcasecmp(v, "yes") || !strcmp(v, "1") || !strcasecmp(v, "on"))
		*out = 1;
	else if (!strcasecmp(v, "false") || !strcasecmp(v, "no") || !strcmp(v, "0") ||
		 !strcasecmp(v, "off"))
		*out = 0;
	else
		return -1;
	return 0;
}

static int parse_uint(const char *v, unsigned long long min, unsigned long long max,
		      unsigned long long *out)
{
	char *end;
	errno = 0;
	if (!*v || *v == '-')
		return -1;
	unsigned long long n = strtoull(v, &end, 10);
	if (*end || errno || n < min || n > max)
		return -1;
	*out = n;
	return 0;
}

static int parse_doubles(const char *v, double *out, int n)
{
	const char *p = v;
	for (int i = 0; i < n; i++) {
		char *end;
		errno = 0;
		out[i] = strtod(p, &end);
		if (end == p || errno || !isfinite(out[i]))
			return -1;
		p = end;
		while (*p == ' ')
			p++;
		if (i < n - 1) {
			if (*p != ',')
				return -1;
			p++;
		}
	}
	return *p ? -1 : 0;
}

static int copy_str(char *dst, size_t cap, const char *v)
{
	size_t n = strlen(v);
	if (n == 0 || n >= cap)
		return -1;
	memcpy(dst, v, n + 1);
	return 0;
}

/* A configuration is a few kilobytes; anything far larger is not one. */
#define CONFIG_MAX_BYTES (1 << 20)

#define BAD(what) fail(msg, len, "[%s] %s: '%s' %s", section, key, value, what)

/*
 * [source] intrinsics = fx,fy,cx,cy: four numbers in pixels, plausible for some image
 * of at most DAO_MAX_DIMENSION pixels a side (the library checks them against the
 * source's size at its first frame); a camera file given here is pointed to
 * intrinsics_file.
 */
static int set_intrinsics(struct daemon_config *c, const char *section, const char *key,
			  const char *value, char *msg, size_t len)
{
	double *v = c->intrinsics;
	if (parse_doubles(value, v, 4)) {
		if (strchr(value, '/') || strstr(value, ".yaml") || strstr(value, ".yml") ||
		    strstr(value, ".json"))
			return BAD("is not four numbers: a camera file goes in intrinsics_file = PATH");
		return BAD("must be four numbers fx,fy,cx,cy in pixels, separated by commas, none "
			   "out of range or infinite "
			   "(e.g. 525,525,319.5,239.5)");
	}
	const double fmax = (double)DAO_MAX_DIMENSION * DAO_CAMERA_FOCAL_MAX_MUL,
		     cmin = -(double)DAO_MAX_DIMENSION, cmax = 2.0 * DAO_MAX_DIMENSION;
	for (int i = 0; i < 2; i++)
		if (!(v[i] > 0 && v[i] <= fmax))
			return fail(msg, len, "[%s] %s: focal length %s=%g is implausible: give "
				    "pixels in (0, %g], the camera's own (its CameraInfo's K, or "
				    "intrinsics_file = PATH with its camera file)",
				    section, key, i ? "fy" : "fx", v[i], fmax);
	for (int i = 2; i < 4; i++)
		if (!(v[i] >= cmin && v[i] <= cmax))
			return fail(msg, len, "[%s] %s: principal point %s=%g is implausible: give "
				    "pixels, near the image centre (from %g to %g at most)",
				    section, key, i == 2 ? "cx" : "cy", v[i], cmin, cmax);
	c->has_intrinsics = 1;
	return 0;
}

static int set_source(struct daemon_config *c, const char *section, const char *key,
		      const char *value, char *msg, size_t len)
{
	unsigned long long n;
	if (!strcmp(key, "uri"))
		return copy_str(c->source_uri, sizeof c->source_uri, value) ? BAD("is empty or too long")
									      : 0;
	if (!strcmp(key, "playback")) {
		if (!strcmp(value, "realtime"))
			c->playback = DAO_PLAYBACK_REALTIME;
		else if (!strcmp(value, "manual"))
			c->playback = DAO_PLAYBACK_MANUAL;
		else
			return BAD("must be realtime or manual");
		return 0;
	}
	if (!strcmp(key, "loop"))
		return parse_bool(value, &c->loop) ? BAD("must be true or false") : 0;
	if (!strcmp(key, "start")) {
		if (parse_uint(value, 0, UINT32_MAX, &n))
			return BAD("must be a frame number >= 0");
		c->start = (uint32_t)n;
		return 0;
	}
	if (!strcmp(key, "depth_unit")) {
		double u;
		if (parse_doubles(value, &u, 1) || !(u > 0 && u <= 1))
			return BAD("must be metres per count in (0, 1]");
		c->depth_unit = (float)u;
		return 0;
	}
	if (!strcmp(key, "intrinsics"))
		return set_intrinsics(c, section, key, value, msg, len);
	if (!strcmp(key, "intrinsics_file")) {
		struct dao_camera cam;
		char m[560];
		if (copy_str(c->intrinsics_file, sizeof c->intrinsics_file, value))
			return BAD("is empty or too long");
		if (camera_file_load(value, &cam, c->camera_warning, sizeof c->camera_warning, m,
				     sizeof m))
			return fail(msg, len, "[%s] %s: %s", section, key, m);
		c->file_width = cam.width;
		c->file_height = cam.height;
		c->file_intrinsics[0] = cam.fx;
		c->file_intrinsics[1] = cam.fy;
		c->file_intrinsics[2] = cam.cx;
		c->file_intrinsics[3] = cam.cy;
		c->has_intrinsics_file = 1;
		return 0;
	}
	if (!strcmp(key, "fov")) {
		if (parse_doubles(value, c->fov_deg, 2) || !(c->fov_deg[0] > 0 && c->fov_deg[0] < 180) ||
		    !(c->fov_deg[1] > 0 && c->fov_deg[1] < 180))
			return BAD("must be H,V in degrees, each in (0, 180)");
		c->has_fov = 1;
		return 0;
	}
	if (!strcmp(key, "retry_initial_ms") || !strcmp(key, "retry_max_ms")) {
		if (parse_uint(value, 10, 3600000, &n))
			return BAD("must be milliseconds in 10..3600000");
		*(key[6] == 'i' ? &c->retry_initial_ms : &c->retry_max_ms) = (unsigned)n;
		return 0;
	}
	if (!strcmp(key, "queue")) {
		if (parse_uint(value, 1, 64, &n))
			return BAD("must be a frame count in 1..64");
		c->input_queue = (unsigned)n;
		return 0;
	}
	if (!strcmp(key, "max_pixels"))
		return pixel_limit_parse(value, &c->max_pixels)
			       ? BAD("must be a pixel count or WxH, at most 16384x16384")
			       : 0;
	return fail(msg, len, "[%s] %s: unknown key (keys: uri, playback, loop, start, depth_unit, "
		    "intrinsics, intrinsics_file, fov, retry_initial_ms, retry_max_ms, queue, "
		    "max_pixels)", section, key);
}

static int set_ao(struct daemon_config *c, const char *section, const char *key,
		  const char *value, char *msg, size_t len)
{
	struct dao_error err;
	if (!strcmp(key, "quality")) {
		if (dao_quality_parse(value, &c->quality, &err))
			return fail(msg, len, "[%s] %s: %s", section, key, err.message);
		return 0;
	}
	if (!dao_param_find(key))
		return fail(msg, len, "[%s] %s: unknown AO parameter (see 'depthao process --help')",
			    section, key);
	struct dao_params scratch;
	dao_params_init(&scratch, DAO_QUALITY_DEFAULT);
	if (dao_params_set(&scratch, key, value, &err))
		return fail(msg, len, "[%s] %s: %s", section, key, err.message);
	for (unsigned i = 0; i < c->nao; i++) { /* a later setting replaces an earlier one */
		if (dao_param_find(c->ao[i].key) == dao_param_find(key)) {
			snprintf(c->ao[i].value, sizeof c->ao[i].value, "%s", value);
			return 0;
		}
	}
	if (c->nao == DAOD_MAX_AO_KEYS || strlen(value) >= sizeof c->ao[0].value)
		return fail(msg, len, "[%s] %s: too many settings or value too long", section, key);
	snprintf(c->ao[c->nao].key, sizeof c->ao[0].key, "%s", key);
	snprintf(c->ao[c->nao].value, sizeof c->ao[0].value, "%s", value);
	c->nao++;
	return 0;
}

static struct sink_config *sink_named(struct daemon_config *c, const char *name, int create)
{
	for (unsigned i = 0; i < c->nsinks; i++)
		if (!strcmp(c->sinks[i].name, name))
			return &c->sinks[i];
	if (!create || c->nsinks == DAOD_MAX_SINKS || strlen(name) >= sizeof c->sinks[0].name)
		return NULL;
	struct sink_config *s = &c->sinks[c->nsinks++];
	memset(s, 0, sizeof(*s));
	snprintf(s->name, sizeof s->name, "%s", name);
	s->stream = STREAM_SHADED;
	s->queue = 8;
	return s;
}

static int set_sink(struct daemon_config *c, const char *section, const char *key,
		    const char *value, char *msg, size_t len)
{
	const char *name = section + 5;
	unsigned long long n;
	if (!*name)
		return fail(msg, len, "[%s]: a sink section needs a name, e.g. [sink.preview]", section);
	struct sink_config *s = sink_named(c, name, 1);
	if (!s)
		return fail(msg, len, "[%s]: too many sinks (at most %d) or name too long", section,
			    DAOD_MAX_SINKS);
	if (!strcmp(key, "uri"))
		return copy_str(s->uri, sizeof s->uri, value) ? BAD("is empty or too long") : 0;
	if (!strcmp(key, "stream")) {
		for (int k = 0; k < STREAM_COUNT; k++) {
			if (!strcmp(value, stream_names[k])) {
				s->stream = (enum stream_kind)k;
				return 0;
			}
		}
		return BAD("must be shaded, ao, ao8, depth, overlay or filtered-depth");
	}
	if (!strcmp(key, "queue")) {
		if (parse_uint(value, 1, 64, &n))
			return BAD("must be a frame count in 1..64");
		s->queue = (unsigned)n;
		return 0;
	}
	return fail(msg, len, "[%s] %s: unknown key (keys: uri, stream, queue)", section, key);
}

static int set_daemon(struct daemon_config *c, const char *section, const char *key,
		      const char *value, char *msg, size_t len)
{
	unsigned long long n;
	if (!strcmp(key, "socket"))
		return copy_str(c->socket_path, sizeof c->socket_path, value)
			       ? BAD("is empty or longer than 107 bytes")
			       : 0;
	if (!strcmp(key, "socket_group"))
		return copy_str(c->socket_group, sizeof c->socket_group, value)
			       ? BAD("is empty or longer than 63 bytes")
			       : 0;
	if (!strcmp(key, "socket_idle_timeout")) {
		if (parse_uint(value, 1, 86400, &n))
			return BAD("must be seconds in 1..86400");
		c->socket_idle_timeout_s = (unsigned)n;
		return 0;
	}
	if (!strcmp(key, "stats_interval")) {
		if (parse_uint(value, 0, 86400, &n))
			return BAD("must be seconds in 0..86400 (0 = off)");
		c->stats_interval_s = (unsigned)n;
		return 0;
	}
	if (!strcmp(key, "stats_json"))
		return copy_str(c->stats_json, sizeof c->stats_json, value) ? BAD("is empty or too long")
									      : 0;
	if (!strcmp(key, "log_level")) {
		int l = log_level_parse(value);
		if (l < 0)
			return BAD("must be error, warn, info or debug");
		c->log_level = l;
		return 0;
	}
	if (!strcmp(key, "drain_on_stop"))
		return parse_bool(value, &c->drain_on_stop) ? BAD("must be true or false") : 0;
	if (!strcmp(key, "max_frames")) {
		if (parse_uint(value, 0, UINT64_MAX, &n))
			return BAD("must be a frame count >= 0 (0 = no limit)");
		c->max_frames = n;
		return 0;
	}
	return fail(msg, len, "[%s] %s: unknown key (keys: socket, socket_group, "
		    "socket_idle_timeout, stats_interval, stats_json, log_level, drain_on_stop, "
		    "max_frames)", section, key);
}

int config_set(struct daemon_config *c, const char *section, const char *key, const char *value,
	       char *msg, size_t len)
{
	if (!strcmp(section, "source"))
		return set_source(c, section, key, value, msg, len);
	if (!strcmp(section, "ao"))
		return set_ao(c, section, key, value, msg, len);
	if (!strncmp(section, "sink.", 5))
		return set_sink(c, section, key, value, msg, len);
	if (!strcmp(section, "daemon"))
		return set_daemon(c, section, key, value, msg, len);
	if (!*section)
		return fail(msg, len, "%s: key outside any section (sections: [source], [ao], "
			    "[sink.NAME], [daemon])", key);
	return fail(msg, len, "[%s]: unknown section (sections: [source], [ao], [sink.NAME], "
		    "[daemon])", section);
}

static int on_pair(void *user, const char *section, const char *key, const char *value,
		   char *msg, size_t len)
{
	return config_set(user, section, key, value, msg, len);
}

int config_load(struct daemon_config *c, const char *path, char *msg, size_t len)
{
	const size_t n = strlen(path);
	if (n >= sizeof c->path)
		return fail(msg, len, "%s: path too long", path);
	/* (memcpy: gcc 12 with UBSan's checks saw a null %s argument in snprintf here) */
	memcpy(c->path, path, n + 1);
	if (!strcmp(path, "/dev/null"))
		return 0; /* an empty configuration: everything from --set, --source, --sink */
	struct dao_error err;
	int fd = dao_input_file_open(path, "configuration file", CONFIG_MAX_BYTES, NULL, &err);
	if (fd < 0)
		return fail(msg, len, "%s", err.message);
	FILE *f = fdopen(fd, "r");
	if (!f) {
		int e = errno;
		close(fd);
		return fail(msg, len, "%s: cannot read: %s", path, strerror(e));
	}
	unsigned line;
	char m[600];
	int r = ini_file_parse(f, on_pair, c, &line, m, sizeof m);
	int e = errno;
	fclose(f);
	if (r == -2)
		return fail(msg, len, "%s:%u: cannot read: %s", path, line, strerror(e));
	if (r < 0)
		return fail(msg, len, "%s:%u: %s", path, line, m);
	return 0;
}

int config_params(const struct daemon_config *c, struct dao_params *out, char *msg, size_t len)
{
	struct dao_error err;
	dao_params_init(out, c->quality);
	/* a source is a stream of consecutive frames: the temporal depth filter
	 * on unless [ao] depth-temporal = 0 */
	dao_params_stream_defaults(out);
	for (unsigned i = 0; i < c->nao; i++)
		if (dao_params_set(out, c->ao[i].key, c->ao[i].value, &err))
			return fail(msg, len, "[ao] %s: %s", c->ao[i].key, err.message);
	if (dao_params_validate(out, &err))
		return fail(msg, len, "[ao]: %s", err.message);
	return 0;
}

/*
 * The directory an images sink writes into, without trailing slashes, in dir
 * (cap bytes): "images:DIR[?k=v...]", or a bare URI naming an existing
 * directory (what the sink's probe takes); 0, or -1 for other sinks.
 */
static int images_dir(const char *uri, char *dir, size_t cap)
{
	struct stat st;
	const char *p = uri;
	if (!strncmp(uri, "images:", 7))
		p = uri + 7;
	else if (stat(uri, &st) != 0 || !S_ISDIR(st.st_mode))
		return -1;
	size_t n = dao_uri_path_len(p, NULL); /* as the sink splits it */
	while (n > 1 && p[n - 1] == '/')
		n--;
	if (n == 0 || n >= cap)
		return -1;
	memcpy(dir, p, n);
	dir[n] = '\0';
	return 0;
}

int config_check(const struct daemon_config *c, char *msg, size_t len)
{
	const char *where = c->path[0] ? c->path : "command line";
	struct dao_params p;
	char m[400];
	if (!c->source_uri[0])
		return fail(msg, len, "%s: [source] uri is required (or --source URI)", where);
	if (c->nsinks == 0)
		return fail(msg, len, "%s: no sinks: add a [sink.NAME] section with uri = ... (or "
			    "--sink NAME=URI)", where);
	for (unsigned i = 0; i < c->nsinks; i++)
		if (!c->sinks[i].uri[0])
			return fail(msg, len, "%s: [sink.%s] uri is required", where, c->sinks[i].name);
	/* two images sinks in one directory: the same file names, one's frames replace the
	 * other's and keep= of one removes the other's */
	for (unsigned i = 0; i < c->nsinks; i++) {
		char a[DAOD_MAX_URI], b[DAOD_MAX_URI];
		if (images_dir(c->sinks[i].uri, a, sizeof a) < 0)
			continue;
		for (unsigned k = i + 1; k < c->nsinks; k++)
			if (images_dir(c->sinks[k].uri, b, sizeof b) == 0 && !strcmp(a, b))
				return fail(msg, len, "%s: [sink.%s] and [sink.%s] both write PNGs into "
					    "%s: their files have the same names (the frame number), so "
					    "one's frames would replace the other's; give each images sink "
					    "its own directory", where, c->sinks[i].name, c->sinks[k].name, a);
	}
	if (c->has_intrinsics && c->has_fov)
		return fail(msg, len, "%s: [source] give intrinsics or fov, not both", where);
	if (c->has_intrinsics_file && (c->has_intrinsics || c->has_fov))
		return fail(msg, len, "%s: [source] give intrinsics_file alone, not with %s", where,
			    c->has_intrinsics ? "intrinsics" : "fov");
	if (c->retry_initial_ms > c->retry_max_ms)
		return fail(msg, len, "%s: [source] retry_initial_ms %u exceeds retry_max_ms %u", where,
			    c->retry_initial_ms, c->retry_max_ms);
	if (config_params(c, &p, m, sizeof m))
		return fail(msg, len, "%s: %s", where, m);
	return 0;
}
