/* SPDX-License-Identifier: MIT */
/* What the file-reading fuzz targets share: see harness.h. */
#define _GNU_SOURCE /* memfd_create */
#include "harness.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include <depthao/plugin.h>

const char *fuzz_temp_dir(void)
{
	static char dir[64];
	if (!dir[0]) {
		snprintf(dir, sizeof dir, "%s", "/tmp/fuzz-depthao.XXXXXX");
		if (!mkdtemp(dir))
			abort();
	}
	return dir;
}

static void file_init(struct fuzz_file *f, const char *name, const char *scheme)
{
	f->fd = -1;
#ifdef MFD_CLOEXEC
	f->fd = memfd_create(name, MFD_CLOEXEC);
	if (f->fd >= 0) {
		snprintf(f->path, sizeof f->path, "/proc/self/fd/%d", f->fd);
		if (access(f->path, R_OK) != 0) {
			close(f->fd);
			f->fd = -1;
		}
	}
#endif
	if (f->fd < 0) /* a plain file, rewritten for every input */
		snprintf(f->path, sizeof f->path, "%s/%s", fuzz_temp_dir(), name);
	if (scheme)
		snprintf(f->uri, sizeof f->uri, "%s:%s", scheme, f->path);
	else
		snprintf(f->uri, sizeof f->uri, "%s", f->path);
}

void fuzz_file_store(struct fuzz_file *f, const char *name, const char *scheme,
		     const uint8_t *data, size_t size)
{
	if (!f->path[0])
		file_init(f, name, scheme);
	if (f->fd >= 0) {
		if (ftruncate(f->fd, 0) != 0 || pwrite(f->fd, data, size, 0) != (ssize_t)size)
			abort();
		return;
	}
	fuzz_write_file(f->path, data, size);
}

void fuzz_write_file(const char *path, const uint8_t *data, size_t size)
{
	FILE *fp = fopen(path, "wb");
	if (!fp || (size && fwrite(data, 1, size, fp) != size) || fclose(fp) != 0)
		abort();
}

void fuzz_check_error(int ret, const struct dao_error *err, const int *codes)
{
	while (*codes && *codes != ret)
		codes++;
	if (!*codes || !err->message[0] || err->code != ret)
		abort();
}

static struct dao_plugins *builtin_plugins(void)
{
	static struct dao_plugins *plugins;
	struct dao_error err;
	if (!plugins && dao_plugins_load(&plugins, "", &err) < 0)
		abort();
	return plugins;
}

/* The frame's camera pose: finite and unit, or an error of the poses' codes. */
static void check_pose(struct dao_source *s, const struct dao_source_frame *f)
{
	static const int pose_codes[] = { -ENOENT, -ENOTSUP, -EINVAL, -ENODATA, -ENOTCONN, -ELOOP,
					  -E2BIG, -ENOMEM, -EIO, -EFBIG, 0 };
	struct dao_source_pose pose = DAO_SOURCE_POSE_INIT;
	struct dao_error err = {0};
	int ret = dao_source_frame_pose(s, f, &pose, &err);
	if (ret < 0) {
		fuzz_check_error(ret, &err, pose_codes);
		return;
	}
	double n = 0;
	for (int i = 0; i < 4; i++)
		n += pose.rotation[i] * pose.rotation[i];
	if (ret != 0 || !(fabs(n - 1.0) < 1e-6) ||
	    !isfinite(pose.translation[0] + pose.translation[1] + pose.translation[2]) ||
	    !memchr(pose.description, 0, sizeof pose.description) ||
	    !memchr(pose.warning, 0, sizeof pose.warning))
		abort();
}

/* Reads frames until the end: each one as `in` says, or an error by the rules. */
static void read_to_end(struct dao_source *s, const struct dao_source_info *in, const int *codes)
{
	for (;;) {
		struct dao_source_frame f;
		struct dao_error err = {0};
		int ret = dao_source_read(s, &f, 0, &err);
		if (ret == DAO_SOURCE_EOS)
			return;
		if (ret < 0) {
			fuzz_check_error(ret, &err, codes);
			continue;
		}
		if (f.depth.width != in->width || f.depth.height != in->height ||
		    f.depth.format != in->format)
			abort();
		check_pose(s, &f);
		dao_source_release(s, &f);
	}
}

void fuzz_play_source(const char *uri, uint64_t max_pixels, int64_t frames, const int *codes)
{
	struct dao_source *s = NULL;
	struct dao_error err = {0};
	int ret = dao_source_open_limited(builtin_plugins(), uri, NULL, max_pixels, &s, &err);
	if (ret < 0) {
		if (s)
			abort();
		fuzz_check_error(ret, &err, codes);
		return;
	}
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	if ((uint64_t)in.width * in.height > max_pixels ||
	    (frames ? in.frame_count != frames : in.frame_count <= 0) ||
	    !memchr(in.description, 0, sizeof(in.description)))
		abort();
	if (dao_source_start(s, &err) < 0)
		abort();
	for (int pass = 0; pass < 2; pass++) {
		read_to_end(s, &in, codes);
		if (dao_source_seek(s, 0, &err) < 0)
			abort();
	}
	dao_source_close(s);
}
