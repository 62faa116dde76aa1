/* SPDX-License-Identifier: MIT */
/*
 * Sink plugin "opencv": a video file through cv::VideoWriter, or a window
 * with the stream, an fps overlay and trackbars for radius, slices, steps,
 * thickness and intensity that change the running pipeline (through the
 * host the daemon attaches).
 *
 * URIs: "FILE.avi" (also .mkv, .mp4; "?fourcc=XVID" picks the codec, MJPG by
 * default, which every OpenCV build writes; "&overwrite=true" see below),
 * "window" or "window:TITLE".
 *
 * A video never replaces a file (cv::VideoWriter would): when FILE exists
 * (an earlier run, the daemon restarted after a crash, a sink reopened) the
 * video goes to the first free NAME-1.EXT, NAME-2.EXT, ... (claimed with
 * O_EXCL before OpenCV opens it; said in the host's log), unless
 * overwrite=true.
 * Without a display (no DISPLAY or WAYLAND_DISPLAY) the window is -ENOTSUP:
 * the daemon then leaves it off instead of retrying.  Closing the window
 * ends the sink (-ECANCELED).
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <depthao/params.h>
#include <depthao/plugin.h>

#include "cv_shim.h"

#define MAX_CONTROLS 5
#define NUMBERED_MAX 9999

struct cv_sink {
	int window;
	char path[512], title[128];
	char file[540];               /* the video being written: path, or NAME-k.EXT */
	int overwrite;
	int claimed;                  /* file was created empty by us (O_EXCL) */
	char fourcc[4];
	struct dao_sink_format fmt;
	struct cvs_video *video;
	struct cvs_window *win;
	const struct dao_sink_host *host;
	struct cvs_control controls[MAX_CONTROLS];
	int ncontrols;
	struct timespec last;
	double fps;
	unsigned long long frames;    /* written to the video */
};

static int ends_with(const char *s, const char *suffix)
{
	size_t n = strlen(s), k = strlen(suffix);
	return n > k && !strcasecmp(s + n - k, suffix);
}

static const char *const cv_options[] = {"fourcc", "overwrite", NULL};

static int is_video_path(const char *uri)
{
	char path[512];
	snprintf(path, sizeof path, "%.*s", (int)dao_uri_path_len(uri, cv_options), uri);
	return ends_with(path, ".avi") || ends_with(path, ".mkv") || ends_with(path, ".mp4");
}

/* "fourcc=XXXX&overwrite=B" (the library's parser: errors name the key and the value) */
static int parse_options(struct cv_sink *s, const char *text, struct dao_error *err)
{
	struct dao_options *o;
	int r = dao_options_parse(&o, "opencv", text, cv_options, err);
	if (r < 0)
		return r;
	const char *fourcc = dao_options_value(o, "fourcc");
	if (fourcc && strlen(fourcc) != 4)
		r = dao_error_set(err, -EINVAL, "opencv: 'fourcc' must be four characters (e.g. "
				  "MJPG, XVID, mp4v), got '%.80s'", fourcc);
	else if (fourcc)
		memcpy(s->fourcc, fourcc, 4);
	if (r >= 0)
		r = dao_options_get_bool(o, "overwrite", &s->overwrite, err);
	dao_options_free(o);
	return r < 0 ? r : 0;
}

static int cv_probe(const char *uri)
{
	return is_video_path(uri) ? 40 : !strcmp(uri, "window") ? 10 : 0;
}

static int cv_open(const char *uri, void **state, struct dao_error *err)
{
	struct cv_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	if (!strcmp(uri, "window") || !strncmp(uri, "window:", 7)) {
		const char *display = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
		if ((!display || !*display) && (!wl || !*wl)) {
			free(s);
			return dao_error_set(err, -ENOTSUP,
					    "opencv: no display (DISPLAY and WAYLAND_DISPLAY are unset), "
					    "so there is no window");
		}
		s->window = 1;
		snprintf(s->title, sizeof s->title, "%s", uri[6] == ':' ? uri + 7 : "depthao");
	} else if (is_video_path(uri)) {
		if (strlen(uri) >= sizeof s->path) {
			free(s);
			return dao_error_set(err, -ENAMETOOLONG, "opencv: '%s' is longer than %zu bytes",
					    uri, sizeof s->path - 1);
		}
		snprintf(s->path, sizeof s->path, "%s", uri);
		size_t opts_at = dao_uri_path_len(s->path, cv_options);
		memcpy(s->fourcc, "MJPG", 4);
		if (s->path[opts_at]) {
			int r = parse_options(s, s->path + opts_at + 1, err);
			if (r < 0) {
				free(s);
				return r;
			}
			s->path[opts_at] = '\0';
		}
	} else {
		free(s);
		return dao_error_set(err, -EINVAL,
				    "opencv: '%s' is neither a video file (.avi, .mkv, .mp4) nor "
				    "'window[:TITLE]'",
				    uri);
	}
	*state = s;
	return 0;
}

static void cv_attach_host(void *state, const struct dao_sink_host *host)
{
	((struct cv_sink *)state)->host = host;
}

/* Trackbars: the range of each parameter from the library's table, trimmed for a slider. */
static void setup_controls(struct cv_sink *s)
{
	static const struct {
		const char *name;
		double max, step;
	} want[MAX_CONTROLS] = {{"radius", 3.0, 0.05}, {"slices", 8, 1}, {"steps", 32, 1},
				{"thickness", 4.0, 0.05}, {"intensity", 4.0, 0.05}};
	s->ncontrols = 0;
	for (int i = 0; i < MAX_CONTROLS; i++) {
		const struct dao_param_info *pi = dao_param_find(want[i].name);
		char v[64];
		if (!pi || !s->host || !s->host->get_param ||
		    s->host->get_param(s->host->user, want[i].name, v, sizeof v) < 0)
			continue;
		struct cvs_control *c = &s->controls[s->ncontrols++];
		c->name = pi->name;
		c->min = pi->min;
		c->max = pi->max < want[i].max ? pi->max : want[i].max;
		c->step = pi->type == DAO_PARAM_INT ? 1 : want[i].step;
		c->value = atof(v);
	}
}

/* NAME-k.EXT of the path: k before the extension of the file name. */
static void numbered(const char *path, unsigned k, char *out, size_t cap)
{
	const char *slash = strrchr(path, '/');
	const char *base = slash ? slash + 1 : path;
	const char *dot = strrchr(base, '.');
	int stem = (int)(dot && dot != base ? (size_t)(dot - path) : strlen(path));
	snprintf(out, cap, "%.*s-%u%s", stem, path, k, path + stem);
}

/* Picks the file for the video: the path with overwrite, else the first free one of the
 * path and its numbered names, created empty with O_EXCL (OpenCV then opens it). */
static int claim_file(struct cv_sink *s, struct dao_error *err)
{
	snprintf(s->file, sizeof s->file, "%s", s->path);
	if (s->overwrite)
		return 0;
	for (unsigned k = 0; k <= NUMBERED_MAX; k++) {
		if (k)
			numbered(s->path, k, s->file, sizeof s->file);
		int fd = open(s->file, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
		if (fd >= 0) {
			close(fd);
			s->claimed = 1;
			if (k && s->host && s->host->log) {
				char m[1200];
				snprintf(m, sizeof m,
					 "opencv: %s exists; recording to %s instead (a video never "
					 "replaces a file; add ?overwrite=true to replace it)",
					 s->path, s->file);
				s->host->log(s->host->user, DAO_LOG_INFO, m);
			}
			return 0;
		}
		if (errno != EEXIST)
			return dao_error_set(err, -errno, "opencv: cannot create %s: %s", s->file,
					    strerror(errno));
	}
	return dao_error_set(err, -EEXIST,
			    "opencv: %s and its numbered names up to -%d exist; a video never "
			    "replaces a file (add ?overwrite=true to replace it)",
			    s->path, NUMBERED_MAX);
}

/* Closes the video; a file we created that got no frame goes again. */
static void close_video(struct cv_sink *s, int frames)
{
	cvs_video_close(s->video);
	s->video = NULL;
	if (s->claimed && !frames)
		unlink(s->file);
	s->claimed = 0;
}

static int cv_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	struct cv_sink *s = state;
	char msg[400];
	if (fmt->format == DAO_PIXFMT_GRAY16) {
		fmt->format = DAO_PIXFMT_GRAY8; /* 8-bit pictures only: subscribe to ao8 */
		return 0;
	}
	if (fmt->format != DAO_PIXFMT_RGB24 && fmt->format != DAO_PIXFMT_GRAY8)
		return dao_error_set(err, -ENOTSUP,
				    "opencv: takes pictures (the shaded, overlay or ao8 stream), "
				    "not %s frames",
				    fmt->format == DAO_PIXFMT_DEPTH16 ? "depth" : "these");
	s->fmt = *fmt;
	if (s->window) {
		setup_controls(s);
		if (!(s->win = cvs_window_open(s->title, s->controls, s->ncontrols, msg, sizeof msg)))
			return dao_error_set(err, -ENOTSUP, "opencv: %s", msg);
		return 0;
	}
	double fps = fmt->fps > 0 ? fmt->fps : 30.0;
	if (s->video) /* negotiated again before the first frame */
		close_video(s, 0);
	int r = claim_file(s, err);
	if (r < 0)
		return r;
	if (!(s->video = cvs_video_open(s->file, s->fourcc, fps, (int)fmt->width, (int)fmt->height,
					fmt->format == DAO_PIXFMT_RGB24, msg, sizeof msg))) {
		if (s->claimed)
			unlink(s->file);
		s->claimed = 0;
		return dao_error_set(err, -EIO, "opencv: %s", msg);
	}
	return 0;
}

static int cv_write(void *state, const struct dao_frame *f, struct dao_error *err)
{
	struct cv_sink *s = state;
	char msg[400];
	const int channels = f->format == DAO_PIXFMT_RGB24 ? 3 : 1;
	if (s->video) {
		if (cvs_video_write(s->video, f->data, f->stride, msg, sizeof msg) < 0)
			return dao_error_set(err, -EIO, "opencv: %s: %s", s->file, msg);
		s->frames++;
		return 0;
	}
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	if (s->last.tv_sec) {
		double dt = (double)(now.tv_sec - s->last.tv_sec) + (now.tv_nsec - s->last.tv_nsec) / 1e9;
		if (dt > 0)
			s->fps = s->fps ? 0.9 * s->fps + 0.1 / dt : 1 / dt;
	}
	s->last = now;
	char overlay[96];
	snprintf(overlay, sizeof overlay, "%.1f fps", s->fps);
	int moved = cvs_window_show(s->win, f->data, (int)f->width, (int)f->height, f->stride,
				    channels, overlay);
	if (moved < 0)
		return dao_error_set(err, -ECANCELED, "opencv: the window was closed");
	for (int i = 0; i < s->ncontrols; i++) {
		if (!(moved & (1 << i)) || !s->host || !s->host->set_param)
			continue;
		char v[32];
		snprintf(v, sizeof v, "%g", s->controls[i].value);
		s->host->set_param(s->host->user, s->controls[i].name, v);
	}
	return 0;
}

static int cv_close(void *state, struct dao_error *err)
{
	struct cv_sink *s = state;
	(void)err;
	if (s->video)
		close_video(s, s->frames != 0);
	cvs_window_close(s->win);
	free(s);
	return 0;
}

static const struct dao_sink_ops opencv_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = cv_probe,
	.open = cv_open,
	.negotiate = cv_negotiate,
	.write = cv_write,
	.close = cv_close,
	.attach_host = cv_attach_host,
};

static const struct dao_plugin opencv_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "opencv",
	.description = "video files (cv::VideoWriter, MJPG .avi by default) and a window with "
		       "fps and AO trackbars",
	.sink = &opencv_sink_ops,
};

DAO_PLUGIN_DEFINE(opencv_plugin)
