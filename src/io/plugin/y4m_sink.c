/* SPDX-License-Identifier: MIT */
/*
 * Built-in sink "y4m": a YUV4MPEG2 stream (what ffmpeg, ffplay and mpv read
 * from a pipe) to stdout ("-"), a file, an existing FIFO or a character
 * device.  URI: "PATH" or "PATH?overwrite=true".
 *
 * Files: a y4m file cannot be continued after a new header, so a file that
 * exists is never truncated: the stream goes to the first free one of
 * NAME-1.y4m, NAME-2.y4m, ... (said in the host's log), unless
 * overwrite=true.  Written frames are synced (fdatasync) at least once a
 * second while frames come, and at close.  A write that fails (a full disk:
 * -ENOSPC, also after a short write) cuts the partial frame off again, so
 * the file holds the header and whole frames; the stream then stops.
 * FIFOs, character devices and stdout are streams: opened without O_CREAT
 * or O_TRUNC, never replaced.  Directories are refused.
 *
 * The stream header is written at the first write after negotiate:
 *     YUV4MPEG2 W<w> H<h> F<num>:<den> Ip A1:1 C<colorspace>\n
 * then every frame is "FRAME\n" and its planes:
 *     GRAY8  -> Cmono    one 8-bit plane
 *     GRAY16 -> Cmono16  one plane of little-endian 16-bit samples
 *     RGB24  -> C444     Y', Cb, Cr at full resolution, BT.601 limited range
 * Depth is not a picture: DEPTH16 is refused (send the ao or shaded stream).
 *
 * A FIFO is opened non-blocking first, so that a FIFO nobody reads is a
 * clear -ENXIO at open instead of a hang, then switched back to blocking:
 * a slow reader slows the writer down, frames are never cut.  A reader that
 * goes away is -EPIPE (the caller ignores SIGPIPE).
 */
#include <depthao/plugin.h>

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/clock.h"
#include "core/error_internal.h"
#include "file/output_file_internal.h"
#include "plugin/builtin.h"
#include "plugin/output_path.h"

#define Y4M_FRAME_MAGIC "FRAME\n"
#define Y4M_DEFAULT_FPS 30
#define Y4M_SYNC_INTERVAL_MS 1000

struct y4m_sink {
	int fd;
	int is_stdout;
	int regular;                /* a regular file: synced, cut back after a failure */
	char *name;                 /* for messages: the path written or "stdout" */
	char *note;                 /* for the host's log, once it is attached */
	struct dao_sink_host host;
	struct dao_sink_format fmt;
	int negotiated;
	int header_done;
	int failed;                 /* a write failed part-way: the stream is cut */
	char fail_msg[DAO_ERROR_MESSAGE_MAX]; /* what was said about it */
	uint8_t *buf;               /* "FRAME\n" + planes of one frame */
	size_t buf_len;
	uint64_t good;              /* bytes of header and whole frames in a regular file */
	uint64_t frames;
	uint64_t last_sync_ns;
};

static const char *const y4m_options[] = {"overwrite", NULL};

static int y4m_probe(const char *uri)
{
	size_t n = dao_uri_path_len(uri, y4m_options);
	struct stat st;
	if (n > 4 && !strncasecmp(uri + n - 4, ".y4m", 4))
		return 50;
	if (stat(uri, &st) == 0 && S_ISFIFO(st.st_mode))
		return 30; /* a FIFO wants a stream */
	if (!strcmp(uri, "-"))
		return 10; /* the only built-in sink that writes to stdout */
	return 0;
}

/* "overwrite=B" after the '?'. */
static int parse_options(const char *opts, int *overwrite, struct dao_error *err)
{
	struct dao_options *o;
	int r = dao_options_parse(&o, "y4m", opts, y4m_options, err);
	if (r == 0) {
		r = dao_options_get_bool(o, "overwrite", overwrite, err);
		dao_options_free(o);
	}
	return r < 0 ? r : 0;
}

/* FIFOs and character devices: straight into them, never created or truncated. */
static int open_stream(struct y4m_sink *s, const char *path, int fifo, struct dao_error *err)
{
	/* O_NONBLOCK first: a FIFO without reader is ENXIO instead of a hang */
	s->fd = open(path, O_WRONLY | O_CLOEXEC | (fifo ? O_NONBLOCK : 0));
	if (s->fd < 0) {
		int r = -errno;
		if (r == -ENXIO && fifo)
			return dao_error_set(err, r,
					     "y4m: no reader on FIFO %s; start the reader (e.g. "
					     "ffplay %s) first",
					     path, path);
		return dao_error_set(err, r, "y4m: cannot open %s for writing: %s", path,
				     strerror(-r));
	}
	int fl = fcntl(s->fd, F_GETFL);
	if (fl < 0 || fcntl(s->fd, F_SETFL, fl & ~O_NONBLOCK) < 0)
		return dao_error_set(err, -errno, "y4m: cannot make %s blocking: %s", path,
				     strerror(errno));
	return 0;
}

/* A regular file: new, replaced (overwrite), or the first free numbered name. */
static int open_file(struct y4m_sink *s, const char *path, int overwrite, struct dao_error *err)
{
	const int flags = O_WRONLY | O_CREAT | O_CLOEXEC;
	struct stat st;
	int r;
	s->regular = 1;
	if (overwrite && stat(path, &st) == 0 && S_ISREG(st.st_mode) &&
	    (r = dao_output_file_check_replaceable(path, &st, err)) < 0)
		return r;
	s->fd = open(path, flags | (overwrite ? O_TRUNC : O_EXCL), 0666);
	for (unsigned k = 1; s->fd < 0 && errno == EEXIST && k <= DAO_OUTPUT_NUMBERED_MAX; k++) {
		char *name = dao_output_numbered(path, k);
		if (!name)
			return dao_error_set(err, -ENOMEM, "out of memory");
		s->fd = open(name, flags | O_EXCL, 0666);
		if (s->fd >= 0) {
			size_t n = strlen(path) + strlen(name) + 160;
			if ((s->note = malloc(n)))
				snprintf(s->note, n,
					 "y4m: %s exists; writing the stream to %s instead (a y4m "
					 "file is never replaced; add ?overwrite=true to replace it)",
					 path, name);
			free(s->name);
			s->name = name;
			return 0;
		}
		free(name);
	}
	if (s->fd < 0 && errno == EEXIST)
		return dao_error_set(err, -EEXIST,
				     "y4m: %s and its numbered names up to -%u exist; add "
				     "?overwrite=true to replace it",
				     path, DAO_OUTPUT_NUMBERED_MAX);
	if (s->fd < 0)
		return dao_error_set(err, -errno, "y4m: cannot open %s for writing: %s", path,
				     strerror(errno));
	return 0;
}

static int y4m_open(const char *uri, void **state, struct dao_error *err)
{
	int r, overwrite = 0;
	if (!*uri)
		return dao_error_set(err, -EINVAL,
				     "y4m: no output given; use y4m:- (stdout), y4m:FILE or "
				     "y4m:FIFO");
	struct y4m_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->fd = -1;
	s->is_stdout = !strcmp(uri, "-");
	size_t n = dao_uri_path_len(uri, y4m_options);
	if (!(s->name = s->is_stdout ? strdup("stdout") : strndup(uri, n))) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	if (s->is_stdout) {
		s->fd = STDOUT_FILENO;
		*state = s;
		return 0;
	}
	if (uri[n] == '?' && (r = parse_options(uri + n + 1, &overwrite, err)) < 0)
		goto fail;
	char *path = strdup(s->name);
	if (!path) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	struct stat st;
	int exists = stat(path, &st) == 0;
	if (exists && S_ISDIR(st.st_mode))
		r = dao_error_set(err, -EISDIR,
				  "y4m: %s is a directory; give a file, a FIFO or - (stdout)", path);
	else if (exists && (S_ISFIFO(st.st_mode) || S_ISCHR(st.st_mode)))
		r = open_stream(s, path, S_ISFIFO(st.st_mode), err);
	else if (exists && !S_ISREG(st.st_mode))
		r = dao_error_set(err, -EINVAL,
				  "y4m: %s is neither a file, a FIFO nor a character device", path);
	else
		r = open_file(s, path, overwrite, err);
	free(path);
	if (r < 0)
		goto fail;
	s->last_sync_ns = dao_mono_ns();
	*state = s;
	return 0;
fail:
	if (s->fd >= 0)
		close(s->fd);
	free(s->note);
	free(s->name);
	free(s);
	return r;
}

static void y4m_attach_host(void *state, const struct dao_sink_host *host)
{
	struct y4m_sink *s = state;
	s->host = *host;
	if (s->note && host->log)
		host->log(host->user, DAO_LOG_INFO, s->note);
	free(s->note);
	s->note = NULL;
}

static int y4m_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	struct y4m_sink *s = state;
	size_t plane = (size_t)fmt->width * fmt->height;
	size_t len;
	switch (fmt->format) {
	case DAO_PIXFMT_GRAY8:
		len = plane;
		break;
	case DAO_PIXFMT_GRAY16:
		len = 2 * plane;
		break;
	case DAO_PIXFMT_RGB24:
		len = 3 * plane;
		break;
	case DAO_PIXFMT_GRAY_F32:
		fmt->format = DAO_PIXFMT_GRAY16; /* the nearest: 16-bit visibility */
		return 0;
	case DAO_PIXFMT_NORMAL_F32:
		fmt->format = DAO_PIXFMT_RGB24;
		return 0;
	default:
		return dao_error_set(err, -ENOTSUP,
				     "y4m: cannot stream %s frames; y4m takes pictures: "
				     "subscribe it to the ao, ao8 or shaded stream",
				     dao_pixfmt_name(fmt->format));
	}
	len += sizeof(Y4M_FRAME_MAGIC) - 1;
	uint8_t *b = realloc(s->buf, len);
	if (!b)
		return dao_error_set(err, -ENOMEM, "out of memory for a %ux%u y4m frame",
				     fmt->width, fmt->height);
	memcpy(b, Y4M_FRAME_MAGIC, sizeof(Y4M_FRAME_MAGIC) - 1);
	s->buf = b;
	s->buf_len = len;
	s->fmt = *fmt;
	s->negotiated = 1;
	return 0;
}

/* Writes all of buf: short writes, EINTR and (for a non-blocking stdout) EAGAIN. */
static int write_all(struct y4m_sink *s, const uint8_t *buf, size_t len, struct dao_error *err)
{
	while (len) {
		ssize_t k = write(s->fd, buf, len);
		if (k > 0) {
			buf += k;
			len -= (size_t)k;
			continue;
		}
		if (k < 0 && errno == EINTR)
			continue;
		if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
			struct pollfd p = {.fd = s->fd, .events = POLLOUT};
			if (poll(&p, 1, -1) < 0 && errno != EINTR)
				return dao_error_set(err, -errno, "y4m: waiting to write %s: %s",
						     s->name, strerror(errno));
			continue;
		}
		int r = k < 0 ? -errno : -EIO;
		if (r == -EPIPE)
			return dao_error_set(err, r,
					     "y4m: the reader of %s went away (broken pipe); "
					     "nothing more can be written",
					     s->name);
		return dao_error_set(err, r,
				     "y4m: cannot write %s: %s; the stream stops after %llu "
				     "frame%s",
				     s->name, strerror(-r), (unsigned long long)s->frames,
				     s->frames == 1 ? "" : "s");
	}
	return 0;
}

static int sync_due(const struct y4m_sink *s)
{
	return dao_mono_us_since(s->last_sync_ns) >= (int64_t)Y4M_SYNC_INTERVAL_MS * 1000;
}

/* fdatasync; a file removed meanwhile (it has no name) is an error: its frames are lost. */
static int sync_file(struct y4m_sink *s, struct dao_error *err)
{
	struct stat st;
	s->last_sync_ns = dao_mono_ns();
	if (fdatasync(s->fd) != 0)
		return dao_error_set(err, -errno, "y4m: cannot sync %s: %s", s->name,
				     strerror(errno));
	if (fstat(s->fd, &st) == 0 && st.st_nlink == 0)
		return dao_error_set(err, -ENOENT,
				     "y4m: %s was removed while being written (or its directory): "
				     "its %llu frame%s went with it; the stream stops",
				     s->name, (unsigned long long)s->frames, s->frames == 1 ? "" : "s");
	return 0;
}

/* num:den of the frame rate: integers as N:1, NTSC-style rates as N000:1001. */
static void fps_ratio(double fps, unsigned long *num, unsigned long *den)
{
	if (!(fps > 0)) {
		*num = Y4M_DEFAULT_FPS;
		*den = 1;
		return;
	}
	if (fps > 1e6)
		fps = 1e6;
	double k = floor(fps + 0.5);
	if (fabs(fps - k) < 1e-6 * fps) {
		*num = (unsigned long)k;
		*den = 1;
		return;
	}
	k = floor(fps * 1.001 + 0.5); /* 29.97 -> 30000:1001 */
	if (k >= 1 && fabs(fps - k * 1000 / 1001) < 1e-4 * fps) {
		*num = (unsigned long)k * 1000;
		*den = 1001;
		return;
	}
	unsigned long n = (unsigned long)floor(fps * 1000 + 0.5), d = 1000;
	if (n == 0)
		n = 1;
	unsigned long a = n, b = d;
	while (b) {
		unsigned long t = a % b;
		a = b;
		b = t;
	}
	*num = n / a;
	*den = d / a;
}

static int write_header(struct y4m_sink *s, struct dao_error *err)
{
	char h[128];
	unsigned long num, den;
	const char *cs = s->fmt.format == DAO_PIXFMT_GRAY8    ? "mono"
			 : s->fmt.format == DAO_PIXFMT_GRAY16 ? "mono16"
							      : "444";
	fps_ratio(s->fmt.fps, &num, &den);
	int n = snprintf(h, sizeof(h), "YUV4MPEG2 W%u H%u F%lu:%lu Ip A1:1 C%s\n", s->fmt.width,
			 s->fmt.height, num, den, cs);
	return write_all(s, (const uint8_t *)h, (size_t)n, err);
}

/* BT.601 limited range, coefficients x 1000, /255 for 8-bit input, rounded. */
static inline uint8_t bt601(long offset, long cr, long cg, long cb, unsigned r, unsigned g,
			    unsigned b)
{
	long v = offset * 255000 + cr * (long)r + cg * (long)g + cb * (long)b + 127500;
	return (uint8_t)(v / 255000);
}

static void convert(struct y4m_sink *s, const struct dao_frame *f)
{
	const uint32_t W = f->width, H = f->height;
	const size_t plane = (size_t)W * H;
	uint8_t *out = s->buf + sizeof(Y4M_FRAME_MAGIC) - 1;
	for (uint32_t y = 0; y < H; y++) {
		const uint8_t *row = (const uint8_t *)f->data + (size_t)y * (size_t)f->stride;
		uint8_t *o = out + (size_t)y * W;
		if (f->format == DAO_PIXFMT_GRAY8) {
			memcpy(o, row, W);
		} else if (f->format == DAO_PIXFMT_GRAY16) {
			o = out + 2 * (size_t)y * W;
			for (uint32_t x = 0; x < W; x++) {
				uint16_t v;
				memcpy(&v, row + 2 * x, 2); /* host order, maybe unaligned */
				o[2 * x] = (uint8_t)(v & 0xff);
				o[2 * x + 1] = (uint8_t)(v >> 8);
			}
		} else { /* RGB24 -> planes Y', Cb, Cr; all sums stay positive */
			for (uint32_t x = 0; x < W; x++) {
				unsigned r = row[3 * x], g = row[3 * x + 1], b = row[3 * x + 2];
				o[x] = bt601(16, 65481, 128553, 24966, r, g, b);
				o[plane + x] = bt601(128, -37797, -74203, 112000, r, g, b);
				o[2 * plane + x] = bt601(128, 112000, -93786, -18214, r, g, b);
			}
		}
	}
}

/* What a call after a failure says (its message without the "y4m: " it began with). */
static int failed_before(const struct y4m_sink *s, struct dao_error *err)
{
	const char *m = strncmp(s->fail_msg, "y4m: ", 5) ? s->fail_msg : s->fail_msg + 5;
	return dao_error_set(err, s->failed, "y4m: an earlier write or sync failed: %s; the "
			     "stream is cut, open the sink again", m);
}

static int y4m_write(void *state, const struct dao_frame *frame, struct dao_error *err)
{
	struct y4m_sink *s = state;
	int r;
	if (!s->negotiated)
		return dao_error_set(err, -EINVAL, "y4m: write before negotiate");
	if (s->failed)
		return failed_before(s, err);
	if (!s->header_done) {
		if ((r = write_header(s, err)) < 0)
			goto fail;
		s->header_done = 1;
	}
	convert(s, frame);
	if ((r = write_all(s, s->buf, s->buf_len, err)) < 0)
		goto fail;
	s->frames++;
	if (s->regular) {
		s->good = (uint64_t)lseek(s->fd, 0, SEEK_CUR);
		struct dao_error e;
		/* a failed sync cuts the stream, but this frame is in the file: this write
		 * succeeded, the next call reports the failure */
		if (sync_due(s) && (r = sync_file(s, &e)) < 0) {
			s->failed = r;
			snprintf(s->fail_msg, sizeof s->fail_msg, "%s", e.message);
		}
	}
	return 0;
fail:
	s->failed = r;
	snprintf(s->fail_msg, sizeof s->fail_msg, "%s", err ? err->message : strerror(-r));
	/* keep the header and whole frames: cut off what a failed write left */
	if (s->regular && ftruncate(s->fd, (off_t)s->good) == 0)
		lseek(s->fd, (off_t)s->good, SEEK_SET);
	return r;
}

static int y4m_flush(void *state, struct dao_error *err)
{
	struct y4m_sink *s = state;
	/* nothing is buffered (every write hands whole frames to the kernel); files are synced */
	if (s->failed)
		return failed_before(s, err);
	return s->regular ? sync_file(s, err) : 0;
}

static int y4m_close(void *state, struct dao_error *err)
{
	struct y4m_sink *s = state;
	struct dao_error ignored;
	/* what the file keeps goes to the disk, also after a failure (already reported) */
	int r = s->regular ? sync_file(s, s->failed ? &ignored : err) : 0;
	if (s->failed)
		r = 0;
	if (!s->is_stdout && s->fd >= 0 && close(s->fd) != 0 && errno != EINTR && r == 0)
		r = dao_error_set(err, -errno, "y4m: closing %s failed: %s", s->name,
				  strerror(errno));
	free(s->buf);
	free(s->note);
	free(s->name);
	free(s);
	return r;
}

static const struct dao_sink_ops y4m_sink_ops = {
	.probe = y4m_probe,
	.open = y4m_open,
	.negotiate = y4m_negotiate,
	.write = y4m_write,
	.flush = y4m_flush,
	.close = y4m_close,
	.attach_host = y4m_attach_host,
};

const struct dao_plugin dao_builtin_y4m_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "y4m",
	.description = "YUV4MPEG2 stream (ffmpeg, ffplay, mpv) to stdout (-), a file or a FIFO",
	.sink = &y4m_sink_ops,
};
