/* SPDX-License-Identifier: MIT */
#define _XOPEN_SOURCE 700
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/test_common.h"

int dao_test_data_path(const char *rel, char *buf, size_t len)
{
	const char *root = getenv("DAO_SHARED_DATA");
	if (!root)
		root = "../shared/data";
	snprintf(buf, len, "%s/%s", root, rel);
	return access(buf, R_OK) == 0 ? 0 : -1;
}

/* the directories made by dao_test_tmpdir, removed when the test exits */
#define MAX_TMPDIRS 64
static char tmpdirs[MAX_TMPDIRS][512];
static int n_tmpdirs;
static pid_t tmpdir_owner;

static int remove_entry(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
	(void)st, (void)type, (void)ftw;
	if (remove(path) != 0)
		fprintf(stderr, "test clean-up: cannot remove %s\n", path);
	return 0;
}

static void remove_tmpdirs(void)
{
	/* a forked child that exits must not take its parent's directories with it */
	if (getpid() != tmpdir_owner || getenv("DAO_TEST_KEEP_TMP"))
		return;
	for (int i = 0; i < n_tmpdirs; i++)
		nftw(tmpdirs[i], remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

const char *dao_test_tmpdir(const char *tag)
{
	static char path[512];
	const char *base = getenv("TMPDIR");
	if (!base)
		base = "/tmp";
	snprintf(path, sizeof path, "%s/dao-test-%s-XXXXXX", base, tag);
	if (!mkdtemp(path)) {
		perror("mkdtemp");
		exit(1);
	}
	if (n_tmpdirs == 0) {
		tmpdir_owner = getpid();
		atexit(remove_tmpdirs);
	}
	if (n_tmpdirs < MAX_TMPDIRS)
		snprintf(tmpdirs[n_tmpdirs++], sizeof tmpdirs[0], "%s", path);
	return path;
}

float *dao_test_ao_of_depth(const struct dao_camera *cam, const float *depth, int algorithm,
			    int thickness_mode, float thickness)
{
	const uint32_t w = cam->width, h = cam->height;
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.algorithm = algorithm;
	p.vbao_thickness_mode = thickness_mode;
	p.vbao_thickness = thickness;
	p.threads = 2;
	struct dao_context *ctx;
	struct dao_error err;
	float *ao = malloc((size_t)w * h * sizeof(float));
	if (!ao || dao_context_create(&ctx, cam, &p, &err)) {
		fprintf(stderr, "dao_test_ao_of_depth: %s\n", ao ? err.message : "out of memory");
		free(ao);
		return NULL;
	}
	const struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
			.stride = (int32_t)w * 4,
				      .data = (void *)(uintptr_t)depth};
	struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = w, .height = h,
			.stride = (int32_t)w * 4, .data = ao};
	const int r = dao_context_process(ctx, &in, NULL, 0, &out, &err);
	dao_context_destroy(ctx);
	if (r) {
		fprintf(stderr, "dao_test_ao_of_depth: %s\n", err.message);
		free(ao);
		return NULL;
	}
	return ao;
}

int dao_test_open_kinect(struct dao_oni_reader **rd, int *stream,
			 const struct dao_oni_stream_info **si, struct dao_camera *cam)
{
	char path[1024];
	if (dao_test_data_path("oni/3DJ_test.oni", path, sizeof path)) {
		printf("SKIP: ../shared/data/oni/3DJ_test.oni not found\n");
		return DAO_TEST_SKIP;
	}
	struct dao_error err;
	if (dao_oni_reader_open(path, rd, &err)) {
		printf("FAIL: %s\n", err.message);
		return 1;
	}
	*stream = dao_oni_reader_depth_stream(*rd, &err);
	*si = dao_oni_reader_stream(*rd, (uint32_t)*stream);
	dao_camera_from_fov(cam, (*si)->width, (*si)->height, (*si)->hfov, (*si)->vfov, NULL);
	return 0;
}
