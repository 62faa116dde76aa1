/* SPDX-License-Identifier: MIT */
/*
 * Source plugin "openni2": depth (and colour) from OpenNI2 devices and .oni
 * recordings through OpenNI2's C API.
 *
 * URIs: "any" (first device), a device URI as `depthao devices` lists it,
 * "Dummy" (OpenNI2's synthetic device), or the path of an .oni file.
 *
 * Files: manual playback is OpenNI2's speed -1 (one frame per read, none
 * lost), real time is speed 1.  OpenNI2's seek command crashes in the
 * Debian build (a pointer to a dead stack value in Device::invoke), so
 * seeking reads forward in manual mode and discards frames, reopening the
 * file to go backwards.
 *
 * OpenNI2's player thread walks its stream list without a lock whenever it
 * is not waiting for a manual trigger (streams stopped, or spinning at the
 * end of a file with repeat off), so destroying a stream then can crash it.
 * Hence: repeat is always on inside OpenNI2 and the end of a recording is
 * decided here from the frame count; before streams are destroyed the
 * player is put in manual mode, given a moment to park on its trigger, and
 * the streams are destroyed while still started.
 *
 * OpenNI2 is initialised on first use and never shut down: oniShutdown()
 * crashes the process once the Dummy device has been used (its driver's
 * thread outlives the unloaded code; seen with Debian's 2.2.0.33), and
 * initialising again is a no-op that only counts.  Streams are stopped and
 * destroyed and devices closed on close, in that order.
 */
#include <errno.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

/* OpenNI2's C headers use these tags without declaring them, and declare
 * functions without prototypes: () instead of (void). */
typedef struct _OniDevice _OniDevice;
typedef struct _OniStream _OniStream;
typedef struct _OniRecorder _OniRecorder;
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wstrict-prototypes"
#include <OniCAPI.h>
#pragma GCC diagnostic pop

#include <depthao/plugin.h>


struct ni_source {
	char uri[512];
	int is_file;
	struct dao_source_options opts;
	OniDeviceHandle dev;
	OniStreamHandle depth, color;
	OniCallbackHandle callbacks;
	atomic_int disconnected, eof;
	int started, ended;
	int frame_count;         /* files */
	int last_index;          /* frameIndex of the last depth frame read (files: 1-based) */
	uint64_t delivered;
	OniFrame *depth_frame, *color_frame;
	struct dao_source_info info;
	char device_uri[256];
};

static int probe(const char *uri)
{
	size_t n = strlen(uri);
	if (!strcmp(uri, "any"))
		return 50;
	if (n > 4 && !strcasecmp(uri + n - 4, ".oni"))
		return 40; /* the built-in reader (60) is preferred for files */
	return 0;
}

/* OpenNI2's last error, without the tabs and newlines it comes with. */
static const char *ni_error(char *buf, size_t cap)
{
	const char *e = oniGetExtendedError();
	size_t k = 0;
	for (; e && *e && k + 1 < cap; e++) {
		char c = (*e == '\t' || *e == '\n' || *e == '\r') ? ' ' : *e;
		if (c == ' ' && (k == 0 || buf[k - 1] == ' '))
			continue;
		buf[k++] = c;
	}
	while (k && buf[k - 1] == ' ')
		k--;
	buf[k] = '\0';
	return k ? buf : "no details";
}

static int ni_status(struct dao_error *err, int code, const char *what)
{
	char e[160];
	return dao_error_set(err, code, "openni2: %s: %s", what, ni_error(e, sizeof(e)));
}

static int list_devices(dao_device_cb cb, void *user, struct dao_error *err)
{
	OniDeviceInfo *list = NULL;
	int n = 0;
	if (oniInitialize(ONI_API_VERSION) != ONI_STATUS_OK)
		return ni_status(err, -EIO, "cannot initialise OpenNI2");
	if (oniGetDeviceList(&list, &n) != ONI_STATUS_OK)
		return ni_status(err, -EIO, "cannot list devices");
	for (int i = 0; i < n; i++) {
		struct dao_device_entry e;
		memset(&e, 0, sizeof(e));
		snprintf(e.uri, sizeof(e.uri), "%s", list[i].uri);
		snprintf(e.name, sizeof(e.name), "%.60s %.60s", list[i].vendor, list[i].name);
		snprintf(e.detail, sizeof(e.detail), "USB %04x:%04x", list[i].usbVendorId,
			 list[i].usbProductId);
		cb(user, &e);
	}
	oniReleaseDeviceList(list);
	return n;
}

static void ONI_CALLBACK_TYPE on_disconnected(const OniDeviceInfo *info, void *cookie)
{
	struct ni_source *s = cookie;
	if (s->device_uri[0] && !strcmp(info->uri, s->device_uri))
		atomic_store(&s->disconnected, 1);
}

static void ONI_CALLBACK_TYPE on_state(const OniDeviceInfo *info, OniDeviceState state,
				       void *cookie)
{
	struct ni_source *s = cookie;
	if (state == ONI_DEVICE_STATE_EOF && s->device_uri[0] && !strcmp(info->uri, s->device_uri))
		atomic_store(&s->eof, 1);
}

static float unit_of(OniPixelFormat f)
{
	return f == ONI_PIXEL_FORMAT_DEPTH_1_MM ? 0.001f
	       : f == ONI_PIXEL_FORMAT_DEPTH_100_UM ? 0.0001f
						   : 0.0f;
}

/* Live devices: prefer 640x480 at 30 fps in millimetres, else any metric mode. */
static void choose_depth_mode(struct ni_source *s)
{
	const OniSensorInfo *si = oniStreamGetSensorInfo(s->depth);
	const OniVideoMode *best = NULL;
	int best_score = -1;
	for (int i = 0; si && i < si->numSupportedVideoModes; i++) {
		const OniVideoMode *m = &si->pSupportedVideoModes[i];
		if (unit_of(m->pixelFormat) == 0.0f)
			continue;
		int score = (m->pixelFormat == ONI_PIXEL_FORMAT_DEPTH_1_MM) * 4 +
			    (m->resolutionX == 640 && m->resolutionY == 480) * 2 + (m->fps == 30);
		if (score > best_score) {
			best_score = score;
			best = m;
		}
	}
	if (best)
		oniStreamSetProperty(s->depth, ONI_STREAM_PROPERTY_VIDEO_MODE, best, sizeof(*best));
}

static void release_frames(struct ni_source *s)
{
	if (s->depth_frame) {
		oniFrameRelease(s->depth_frame);
		s->depth_frame = NULL;
	}
	if (s->color_frame) {
		oniFrameRelease(s->color_frame);
		s->color_frame = NULL;
	}
}

static int set_speed(struct ni_source *s, float speed);

/* Files: park OpenNI2's player thread on its manual trigger (see the top). */
static void park_player(struct ni_source *s)
{
	if (!s->is_file || !s->dev)
		return;
	set_speed(s, -1.0f);
	struct timespec nap = {0, 30 * 1000 * 1000};
	nanosleep(&nap, NULL);
}

static void close_device(struct ni_source *s)
{
	release_frames(s);
	if (s->is_file && s->started)
		park_player(s);
	else if (s->started) {
		if (s->color)
			oniStreamStop(s->color);
		oniStreamStop(s->depth);
	}
	/* file streams are destroyed while started: the player then stays parked */
	if (s->color) {
		oniStreamDestroy(s->color);
		s->color = NULL;
	}
	if (s->depth) {
		oniStreamDestroy(s->depth);
		s->depth = NULL;
	}
	if (s->dev) {
		oniDeviceClose(s->dev);
		s->dev = NULL;
	}
	s->started = 0;
}

static int set_speed(struct ni_source *s, float speed)
{
	return oniDeviceSetProperty(s->dev, ONI_DEVICE_PROPERTY_PLAYBACK_SPEED, &speed,
				    sizeof(speed)) == ONI_STATUS_OK
		       ? 0
		       : -EIO;
}

/* Opens the device (its info into di) and creates its depth and, if wanted, colour streams. */
static int open_streams(struct ni_source *s, OniDeviceInfo *di, struct dao_error *err)
{
	const char *uri = strcmp(s->uri, "any") ? s->uri : NULL;
	if (oniDeviceOpen(uri, &s->dev) != ONI_STATUS_OK) {
		s->dev = NULL;
		char e[160];
		return dao_error_set(err, s->is_file ? -EINVAL : -ENODEV,
				    "openni2: cannot open '%s': %s", s->uri, ni_error(e, sizeof(e)));
	}
	memset(di, 0, sizeof(*di));
	if (oniDeviceGetInfo(s->dev, di) == ONI_STATUS_OK)
		snprintf(s->device_uri, sizeof(s->device_uri), "%s", di->uri);
	if (!oniDeviceGetSensorInfo(s->dev, ONI_SENSOR_DEPTH))
		return dao_error_set(err, -EINVAL, "openni2: '%s' has no depth sensor", s->uri);
	if (s->is_file) {
		OniBool repeat = 1; /* see the top of this file */
		oniDeviceSetProperty(s->dev, ONI_DEVICE_PROPERTY_PLAYBACK_REPEAT_ENABLED, &repeat,
				     sizeof(repeat));
		/* manual until start: skipping to start_frame must not lose frames */
		if (set_speed(s, -1.0f) < 0)
			return ni_status(err, -EIO, "cannot set the playback speed");
	}
	if (oniDeviceCreateStream(s->dev, ONI_SENSOR_DEPTH, &s->depth) != ONI_STATUS_OK) {
		s->depth = NULL;
		return ni_status(err, -EIO, "cannot create the depth stream");
	}
	if (!s->is_file)
		choose_depth_mode(s);
	if (s->opts.want_color && oniDeviceGetSensorInfo(s->dev, ONI_SENSOR_COLOR)) {
		if (oniDeviceCreateStream(s->dev, ONI_SENSOR_COLOR, &s->color) != ONI_STATUS_OK)
			s->color = NULL; /* depth alone is still useful */
	}
	return 0;
}

/* The depth stream's size, unit, field of view, mirroring, registration and frame count. */
static int read_depth_info(struct ni_source *s, struct dao_error *err)
{
	struct dao_source_info *in = &s->info;
	OniVideoMode vm;
	int size = sizeof(vm);
	if (oniStreamGetProperty(s->depth, ONI_STREAM_PROPERTY_VIDEO_MODE, &vm, &size) !=
	    ONI_STATUS_OK)
		return ni_status(err, -EIO, "cannot read the depth video mode");
	in->width = (uint32_t)vm.resolutionX;
	in->height = (uint32_t)vm.resolutionY;
	in->fps = vm.fps;
	in->format = DAO_PIXFMT_DEPTH16;
	in->depth_unit = unit_of(vm.pixelFormat);
	if (in->depth_unit == 0.0f)
		return dao_error_set(err, -EINVAL,
				    "openni2: '%s' delivers depth in pixel format %d, not in "
				    "millimetres or 100 um",
				    s->uri, (int)vm.pixelFormat);
	float fov;
	size = sizeof(fov);
	if (oniStreamGetProperty(s->depth, ONI_STREAM_PROPERTY_HORIZONTAL_FOV, &fov, &size) ==
		    ONI_STATUS_OK &&
	    fov > 0) {
		in->hfov = fov;
		size = sizeof(fov);
		if (oniStreamGetProperty(s->depth, ONI_STREAM_PROPERTY_VERTICAL_FOV, &fov, &size) ==
			    ONI_STATUS_OK &&
		    fov > 0) {
			in->vfov = fov;
			in->has_fov = 1;
		}
	}
	OniBool b = 0;
	size = sizeof(b);
	if (oniStreamGetProperty(s->depth, ONI_STREAM_PROPERTY_MIRRORING, &b, &size) == ONI_STATUS_OK)
		in->mirrored = b != 0;
	int reg = 0;
	size = sizeof(reg);
	if (oniDeviceGetProperty(s->dev, ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION, &reg, &size) ==
	    ONI_STATUS_OK)
		in->registered = reg != 0;
	in->live = !s->is_file;
	in->frame_count = -1;
	if (s->is_file) {
		int n = 0;
		size = sizeof(n);
		if (oniStreamGetProperty(s->depth, ONI_STREAM_PROPERTY_NUMBER_OF_FRAMES, &n, &size) !=
			    ONI_STATUS_OK ||
		    n <= 0)
			return dao_error_set(err, -EINVAL, "openni2: '%s' has no depth frames", s->uri);
		s->frame_count = n;
		in->frame_count = n;
	}
	return 0;
}

/* The colour stream's size if it delivers RGB888; else the stream is dropped. */
static void read_color_info(struct ni_source *s)
{
	struct dao_source_info *in = &s->info;
	OniVideoMode vm;
	int size = sizeof(vm);
	if (oniStreamGetProperty(s->color, ONI_STREAM_PROPERTY_VIDEO_MODE, &vm, &size) ==
		    ONI_STATUS_OK &&
	    vm.pixelFormat == ONI_PIXEL_FORMAT_RGB888) {
		in->has_color = 1;
		in->color_width = (uint32_t)vm.resolutionX;
		in->color_height = (uint32_t)vm.resolutionY;
	} else {
		oniStreamDestroy(s->color);
		s->color = NULL;
	}
}

/* Opens the device and streams and fills s->info. */
static int open_device(struct ni_source *s, struct dao_error *err)
{
	OniDeviceInfo di;
	int r = open_streams(s, &di, err);
	if (r)
		return r;
	struct dao_source_info *in = &s->info;
	memset(in, 0, sizeof(*in));
	if ((r = read_depth_info(s, err)))
		return r;
	if (s->color)
		read_color_info(s);
	snprintf(in->description, sizeof(in->description), "OpenNI2 %s%.100s: depth %ux%u@%.0f %s%s",
		 s->is_file ? "file " : "", di.name[0] && !s->is_file ? di.name : s->uri,
		 in->width, in->height, in->fps, in->depth_unit == 0.001f ? "1 mm" : "100 um",
		 in->has_color ? " + colour" : "");
	s->last_index = 0;
	return 0;
}

static int ni_open(const char *uri, const struct dao_source_options *opts, void **state,
		   struct dao_error *err)
{
	struct ni_source *s = calloc(1, sizeof(*s));
	int r;
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	if (strlen(uri) >= sizeof(s->uri)) {
		free(s);
		return dao_error_set(err, -EINVAL, "openni2: URI too long");
	}
	size_t n = strlen(uri);
	memcpy(s->uri, uri, n + 1); /* length checked above */
	s->is_file = n > 4 && !strcasecmp(uri + n - 4, ".oni");
	s->opts = *opts;
	if (s->opts.step == 0)
		s->opts.step = 1;
	if (s->is_file) {
		FILE *f = fopen(uri, "rb"); /* OpenNI2's own message for a missing file is vague */
		if (!f) {
			r = dao_error_set(err, -errno, "openni2: cannot open %s: %s", uri, strerror(errno));
			free(s);
			return r;
		}
		fclose(f);
	}
	if (oniInitialize(ONI_API_VERSION) != ONI_STATUS_OK) {
		r = ni_status(err, -EIO, "cannot initialise OpenNI2");
		free(s);
		return r;
	}
	OniDeviceCallbacks cbs = {NULL, on_disconnected, on_state};
	if (oniRegisterDeviceCallbacks(&cbs, s, &s->callbacks) != ONI_STATUS_OK)
		s->callbacks = NULL;
	if ((r = open_device(s, err)) < 0)
		goto fail;
	if (s->is_file && opts->start_frame >= (uint32_t)s->frame_count) {
		r = dao_error_set(err, -EINVAL, "openni2: start frame %u is past the end of %s (%d frames)",
				 opts->start_frame, uri, s->frame_count);
		goto fail;
	}
	*state = s;
	return 0;
fail:
	close_device(s);
	if (s->callbacks)
		oniUnregisterDeviceCallbacks(s->callbacks);
	free(s);
	return r;
}

static void ni_get_info(void *state, struct dao_source_info *info)
{
	*info = ((struct ni_source *)state)->info;
}

static int start_streams(struct ni_source *s, struct dao_error *err)
{
	if (oniStreamStart(s->depth) != ONI_STATUS_OK)
		return ni_status(err, s->is_file ? -EIO : -ENODEV, "cannot start the depth stream");
	if (s->color && oniStreamStart(s->color) != ONI_STATUS_OK) {
		oniStreamDestroy(s->color);
		s->color = NULL;
		s->info.has_color = 0;
	}
	s->started = 1;
	return 0;
}

/* Waits for the next depth frame and keeps it in s->depth_frame. */
static int next_depth(struct ni_source *s, int timeout_ms, struct dao_error *err)
{
	int idx;
	if (s->depth_frame) {
		oniFrameRelease(s->depth_frame);
		s->depth_frame = NULL;
	}
	if (atomic_load(&s->disconnected))
		return dao_error_set(err, -ENODEV, "openni2: device '%s' was disconnected", s->uri);
	OniStatus st = oniWaitForAnyStream(&s->depth, 1, &idx, timeout_ms);
	if (st == ONI_STATUS_TIME_OUT) {
		if (atomic_load(&s->disconnected))
			return dao_error_set(err, -ENODEV, "openni2: device '%s' was disconnected", s->uri);
		return -EAGAIN;
	}
	if (st != ONI_STATUS_OK)
		return ni_status(err, s->is_file ? -EIO : -ENODEV, "waiting for a depth frame failed");
	if (oniStreamReadFrame(s->depth, &s->depth_frame) != ONI_STATUS_OK) {
		s->depth_frame = NULL;
		return ni_status(err, s->is_file ? -EIO : -ENODEV, "reading a depth frame failed");
	}
	s->last_index = s->depth_frame->frameIndex;
	return 0;
}

/* Files: reads and discards frames until the next read delivers 1-based `target`. */
static int skip_to(struct ni_source *s, int target, struct dao_error *err)
{
	while (s->last_index + 1 < target) {
		int r = next_depth(s, 5000, err);
		if (r == -EAGAIN)
			return dao_error_set(err, -EIO, "openni2: no frame within 5 s while seeking");
		if (r < 0)
			return r;
	}
	return 0;
}

static int ni_start(void *state, struct dao_error *err)
{
	struct ni_source *s = state;
	int r;
	if (s->ended)
		return dao_error_set(err, -EINVAL, "openni2: the recording has ended; reopen it");
	if ((r = start_streams(s, err)) < 0)
		return r;
	if (s->is_file) {
		if ((r = skip_to(s, (int)s->opts.start_frame + 1, err)) < 0)
			return r;
		if (s->opts.playback == DAO_PLAYBACK_REALTIME && set_speed(s, 1.0f) < 0)
			return ni_status(err, -EIO, "cannot set real-time playback");
	}
	return 0;
}

/* The end of a recording (decided here: OpenNI2 itself always repeats). */
static int end_of_file(struct ni_source *s)
{
	if (!s->ended && s->opts.playback == DAO_PLAYBACK_REALTIME)
		set_speed(s, -1.0f); /* park the player instead of letting it run on */
	release_frames(s);
	s->ended = 1;
	return DAO_SOURCE_EOS;
}

static void attach_color(struct ni_source *s, struct dao_source_frame *f)
{
	int idx;
	/* colour comes with (or just after) its depth frame; do not wait long for it */
	if (oniWaitForAnyStream(&s->color, 1, &idx, 0) != ONI_STATUS_OK)
		return;
	OniFrame *c = NULL;
	if (oniStreamReadFrame(s->color, &c) != ONI_STATUS_OK)
		return;
	if (s->color_frame)
		oniFrameRelease(s->color_frame);
	s->color_frame = c;
	f->color.format = DAO_PIXFMT_RGB24;
	f->color.width = (uint32_t)c->width;
	f->color.height = (uint32_t)c->height;
	f->color.stride = c->stride;
	f->color.data = c->data;
	f->color.timestamp_ns = c->timestamp * 1000u;
	f->color.sequence = (uint64_t)c->frameIndex;
}

static int ni_read(void *state, struct dao_source_frame *f, int timeout_ms, struct dao_error *err)
{
	struct ni_source *s = state;
	int r;
	if (s->ended)
		return DAO_SOURCE_EOS;
	if (s->is_file && !s->opts.loop && s->last_index >= s->frame_count)
		return end_of_file(s);
	if (s->is_file && s->opts.step > 1 && s->delivered > 0) {
		int target = s->last_index + (int)s->opts.step;
		if (!s->opts.loop && target > s->frame_count)
			return end_of_file(s);
		if (target <= s->frame_count && (r = skip_to(s, target, err)) < 0)
			return r;
	}
	if ((r = next_depth(s, timeout_ms, err)) < 0)
		return r;
	OniFrame *d = s->depth_frame;
	if ((uint32_t)d->width != s->info.width || (uint32_t)d->height != s->info.height ||
	    d->stride < d->width * 2)
		return dao_error_set(err, -EIO, "openni2: frame %d is %dx%d, the stream said %ux%u",
				    d->frameIndex, d->width, d->height, s->info.width, s->info.height);
	f->depth.format = DAO_PIXFMT_DEPTH16;
	f->depth.width = (uint32_t)d->width;
	f->depth.height = (uint32_t)d->height;
	f->depth.stride = d->stride;
	f->depth.data = d->data;
	f->depth.depth_unit = s->info.depth_unit;
	f->depth.timestamp_ns = d->timestamp * 1000u;
	f->depth.sequence = (uint64_t)d->frameIndex;
	f->color.format = DAO_PIXFMT_NONE;
	f->index = s->is_file ? (uint64_t)(d->frameIndex - 1) : s->delivered;
	if (s->color)
		attach_color(s, f);
	s->delivered++;
	return 0;
}

static void ni_release(void *state, struct dao_source_frame *f)
{
	/* frames are released on the next read or on close; nothing to do early */
	(void)state;
	(void)f;
}

static int ni_seek(void *state, uint64_t index, struct dao_error *err)
{
	struct ni_source *s = state;
	int r;
	if (!s->is_file)
		return dao_error_set(err, -ENOTSUP, "openni2: live devices cannot seek");
	if (index >= (uint64_t)s->frame_count)
		return dao_error_set(err, -EINVAL, "openni2: seek to frame %llu: %s has %d frames",
				    (unsigned long long)index, s->uri, s->frame_count);
	int was_started = s->started || s->ended;
	if ((int)index < s->last_index || s->ended) {
		/* backwards: reopen the file and read forward */
		close_device(s);
		s->ended = 0;
		atomic_store(&s->eof, 0);
		if ((r = open_device(s, err)) < 0)
			return r;
		if (was_started && (r = start_streams(s, err)) < 0)
			return r;
	} else if (s->opts.playback == DAO_PLAYBACK_REALTIME && s->started) {
		set_speed(s, -1.0f);
	}
	if (!s->started) {
		s->opts.start_frame = (uint32_t)index; /* applied by start */
		return 0;
	}
	if ((r = skip_to(s, (int)index + 1, err)) < 0)
		return r;
	if (s->opts.playback == DAO_PLAYBACK_REALTIME)
		set_speed(s, 1.0f);
	return 0;
}

static void ni_stop(void *state)
{
	struct ni_source *s = state;
	release_frames(s);
	if (s->is_file) {
		park_player(s); /* streams stay started until close, see the top */
		return;
	}
	if (s->started) {
		if (s->color)
			oniStreamStop(s->color);
		oniStreamStop(s->depth);
		s->started = 0;
	}
}

static void ni_close(void *state)
{
	struct ni_source *s = state;
	close_device(s);
	if (s->callbacks)
		oniUnregisterDeviceCallbacks(s->callbacks);
	free(s);
}

static const struct dao_source_ops openni2_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = probe,
	.list_devices = list_devices,
	.open = ni_open,
	.get_info = ni_get_info,
	.start = ni_start,
	.read = ni_read,
	.release = ni_release,
	.seek = ni_seek,
	.stop = ni_stop,
	.close = ni_close,
};

static const struct dao_plugin openni2_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "openni2",
	.description = "OpenNI2 devices (PrimeSense, Xtion, Kinect via drivers, Orbbec) and .oni "
		       "playback",
	.source = &openni2_source_ops,
};

DAO_PLUGIN_DEFINE(openni2_plugin)
