/* SPDX-License-Identifier: MIT */
/*
 * The images sink's options (issue #16, item 11): compression=0..9 (exact
 * round trips, sizes ordered), keep=N (at most N of the sink's own files,
 * the oldest removed as new ones land, across restarts, rewrites of a
 * looped recording counted once, nothing else in the directory touched),
 * and the errors of bad options.
 */
#define _GNU_SOURCE /* utimensat's AT_FDCWD with _POSIX_C_SOURCE */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "common/test_common.h"

#define W 40
#define H 24

static struct dao_plugins *g_plugins;
static struct dao_frame g_frame; /* GRAY16 */

static int setup(void **state)
{
	(void)state;
	struct dao_error err;
	if (dao_frame_alloc(&g_frame, DAO_PIXFMT_GRAY16, W, H, &err))
		return -1;
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			((uint16_t *)g_frame.data)[y * W + x] = (uint16_t)(x * 1601 + y * 977 + x * y);
	return dao_plugins_load(&g_plugins, "", &err);
}

static int teardown(void **state)
{
	(void)state;
	dao_frame_free(&g_frame);
	dao_plugins_free(g_plugins);
	return 0;
}

static struct dao_sink *open_images(const char *dir, const char *opts)
{
	char uri[1400];
	struct dao_sink *s = NULL;
	struct dao_error err;
	snprintf(uri, sizeof uri, "images:%s%s", dir, opts);
	int r = dao_sink_open(g_plugins, uri, &s, &err);
	if (r)
		fail_msg("open %s: %s", uri, err.message);
	struct dao_sink_format fmt = {.size = sizeof(struct dao_sink_format), .format = DAO_PIXFMT_GRAY16, .width = W, .height = H};
	assert_int_equal(dao_sink_negotiate(s, &fmt, &err), 0);
	return s;
}

static void write_seq(struct dao_sink *s, uint64_t seq)
{
	struct dao_error err;
	g_frame.sequence = seq;
	int r = dao_sink_write(s, &g_frame, &err);
	if (r)
		fail_msg("write %llu: %s", (unsigned long long)seq, err.message);
}

static void close_sink(struct dao_sink *s)
{
	struct dao_error err;
	assert_int_equal(dao_sink_close(s, &err), 0);
}

/* The directory's entries, sorted, joined with ' '. */
static void listing(const char *dir, char *out, size_t len)
{
	struct dirent **names;
	int n = scandir(dir, &names, NULL, alphasort);
	assert_true(n >= 0);
	out[0] = '\0';
	for (int i = 0; i < n; i++) {
		if (strcmp(names[i]->d_name, ".") && strcmp(names[i]->d_name, "..")) {
			size_t k = strlen(out);
			snprintf(out + k, len - k, "%s%s", k ? " " : "", names[i]->d_name);
		}
		free(names[i]);
	}
	free(names);
}

static void touch_file(const char *dir, const char *name, const char *text)
{
	char p[4096];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	FILE *f = fopen(p, "w");
	assert_non_null(f);
	fputs(text, f);
	assert_int_equal(fclose(f), 0);
}

static void set_mtime(const char *dir, const char *name, time_t t)
{
	char p[4096];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	struct timespec ts[2] = {{t, 0}, {t, 0}};
	assert_int_equal(utimensat(AT_FDCWD, p, ts, 0), 0);
}

static void test_keep_counts_names_and_foreign_files(void **state)
{
	(void)state;
	char dir[600], p[1400], list[4096];
	snprintf(dir, sizeof dir, "%s/keep", dao_test_tmpdir("images-keep"));
	assert_int_equal(mkdir(dir, 0777), 0);
	/* not the sink's: other names, other digit counts, other case, a temporary, a link,
	 * a directory with the sink's pattern, a file in a subdirectory */
	const char *foreign[] = {"notes.txt", "12345.png", "0000001.png", "000004.PNG",
				 "000003.png.tmp-abcdef", "frame-000001.png", "000001.png.bak"};
	for (size_t i = 0; i < sizeof foreign / sizeof *foreign; i++)
		touch_file(dir, foreign[i], "x");
	snprintf(p, sizeof p, "%s/000098.png", dir);
	assert_int_equal(mkdir(p, 0777), 0);
	touch_file(p, "000001.png", "inside");
	snprintf(p, sizeof p, "%s/000099.png", dir);
	assert_int_equal(symlink("/nonexistent/target.png", p), 0);

	struct dao_sink *s = open_images(dir, "?keep=5");
	for (uint64_t seq = 1; seq <= 12; seq++) {
		write_seq(s, seq);
		int own = 0;
		for (uint64_t k = 1; k <= 12; k++) {
			snprintf(p, sizeof p, "%s/%06llu.png", dir, (unsigned long long)k);
			own += access(p, F_OK) == 0;
		}
		assert_int_equal(own, seq < 5 ? (int)seq : 5);
	}
	close_sink(s);
	listing(dir, list, sizeof list);
	assert_string_equal(list, "0000001.png 000001.png.bak 000003.png.tmp-abcdef 000004.PNG "
				  "000008.png 000009.png 000010.png 000011.png 000012.png 000098.png "
				  "000099.png 12345.png frame-000001.png notes.txt");
	snprintf(p, sizeof p, "%s/000098.png", dir);
	listing(p, list, sizeof list);
	assert_string_equal(list, "000001.png");

	/* the files read back as written */
	struct dao_frame got;
	struct dao_error err;
	snprintf(p, sizeof p, "%s/000012.png", dir);
	assert_int_equal(dao_png_read(p, &got, &err), 0);
	assert_memory_equal(got.data, g_frame.data, (size_t)W * H * 2);
	dao_frame_free(&got);
}

/* An earlier run's files count, oldest by modification time first. */
static void test_keep_across_restarts(void **state)
{
	(void)state;
	char dir[600], list[4096];
	snprintf(dir, sizeof dir, "%s/restart", dao_test_tmpdir("images-keep"));
	struct dao_sink *s = open_images(dir, "?keep=20");
	for (uint64_t seq = 100; seq < 110; seq++)
		write_seq(s, seq);
	close_sink(s);
	/* ages against the numbers: 000100 is the newest, 000109 the oldest */
	for (int i = 0; i < 10; i++) {
		char name[32];
		snprintf(name, sizeof name, "%06d.png", 100 + i);
		set_mtime(dir, name, 1700000000 - i * 60);
	}
	touch_file(dir, "README", "not a frame");
	set_mtime(dir, "README", 1600000000); /* older than all: still not the sink's */

	/* reopened with keep=5: trimmed to the 5 newest at once */
	s = open_images(dir, "?keep=5");
	listing(dir, list, sizeof list);
	assert_string_equal(list, "000100.png 000101.png 000102.png 000103.png 000104.png README");
	/* the new run numbers from 1 again: the old files go first, oldest first */
	write_seq(s, 1);
	write_seq(s, 2);
	listing(dir, list, sizeof list);
	assert_string_equal(list, "000001.png 000002.png 000100.png 000101.png 000102.png README");
	/* a looped recording rewrites its numbers: each file counts once, as the newest */
	write_seq(s, 1);
	write_seq(s, 3);
	write_seq(s, 4);
	write_seq(s, 2);
	write_seq(s, 5);
	listing(dir, list, sizeof list);
	assert_string_equal(list, "000001.png 000002.png 000003.png 000004.png 000005.png README");
	write_seq(s, 6); /* the oldest is 1: rewritten before 3, 4, 2 and 5 */
	listing(dir, list, sizeof list);
	assert_string_equal(list, "000002.png 000003.png 000004.png 000005.png 000006.png README");
	close_sink(s);

	/* without keep nothing is removed */
	s = open_images(dir, "");
	write_seq(s, 7);
	close_sink(s);
	listing(dir, list, sizeof list);
	assert_string_equal(list, "000002.png 000003.png 000004.png 000005.png 000006.png 000007.png README");
}

static long file_size(const char *p)
{
	struct stat st;
	assert_int_equal(stat(p, &st), 0);
	return (long)st.st_size;
}

static void test_compression(void **state)
{
	(void)state;
	char base[600], dir[700], p[1400];
	snprintf(base, sizeof base, "%s", dao_test_tmpdir("images-compression"));
	long size[10];
	for (int level = 0; level <= 9; level++) {
		char opt[32];
		snprintf(dir, sizeof dir, "%s/c%d", base, level);
		snprintf(opt, sizeof opt, "?compression=%d", level);
		struct dao_sink *s = open_images(dir, opt);
		write_seq(s, 1);
		close_sink(s);
		snprintf(p, sizeof p, "%s/000001.png", dir);
		size[level] = file_size(p);
		struct dao_frame got;
		struct dao_error err;
		assert_int_equal(dao_png_read(p, &got, &err), 0);
		assert_int_equal(got.format, DAO_PIXFMT_GRAY16);
		assert_memory_equal(got.data, g_frame.data, (size_t)W * H * 2);
		dao_frame_free(&got);
	}
	/* 0 stores: every sample plus a filter byte per row and the chunk framing */
	assert_true(size[0] >= W * H * 2 + H);
	assert_true(size[1] < size[0]);
	assert_true(size[9] <= size[2]);
	/* the default is level 1, byte for byte */
	snprintf(dir, sizeof dir, "%s/default", base);
	struct dao_sink *s = open_images(dir, "");
	write_seq(s, 1);
	close_sink(s);
	snprintf(p, sizeof p, "%s/000001.png", dir);
	assert_int_equal(file_size(p), size[1]);
	/* both options together, either order */
	snprintf(dir, sizeof dir, "%s/both", base);
	s = open_images(dir, "?keep=1&compression=0");
	write_seq(s, 1);
	write_seq(s, 2);
	close_sink(s);
	snprintf(p, sizeof p, "%s/000002.png", dir);
	assert_int_equal(file_size(p), size[0]);
	snprintf(p, sizeof p, "%s/000001.png", dir);
	assert_int_equal(access(p, F_OK), -1);
}

static void test_bad_options(void **state)
{
	(void)state;
	char dir[600], uri[1400];
	snprintf(dir, sizeof dir, "%s", dao_test_tmpdir("images-options"));
	const struct {
		const char *opts, *msg;
	} bad[] = {
		{"?compression=10", "images: 'compression' must be an integer in 0..9, got '10'"},
		{"?compression=", "images: option 'compression' has no value"},
		{"?compression=1x", "'compression' must be an integer in 0..9, got '1x'"},
		{"?keep=0", "'keep' must be an integer in 1..10000000, got '0'"},
		{"?keep=-3", "'keep' must be an integer in 1..10000000, got '-3'"},
		{"?keep=10000001", "'keep' must be an integer in 1..10000000"},
		{"?keep=5&colour=red", "unknown option 'colour' (known: compression, keep)"},
		{"?compressionx=1", "unknown option 'compressionx'"},
		{"?keep=5&keep=6", "option 'keep' is given twice"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
		struct dao_sink *s = NULL;
		struct dao_error err;
		snprintf(uri, sizeof uri, "images:%s/o%zu%s", dir, i, bad[i].opts);
		assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -EINVAL);
		assert_null(s);
		if (!strstr(err.message, bad[i].msg))
			fail_msg("%s: '%s' lacks '%s'", uri, err.message, bad[i].msg);
		snprintf(uri, sizeof uri, "%s/o%zu", dir, i);
		assert_int_equal(access(uri, F_OK), -1); /* nothing created */
	}
	/* a '?' without key=value is part of the directory's name */
	snprintf(uri, sizeof uri, "%s/what?", dir);
	struct dao_sink *s = open_images(uri, "");
	write_seq(s, 3);
	close_sink(s);
	snprintf(uri, sizeof uri, "%s/what?/000003.png", dir);
	assert_int_equal(access(uri, F_OK), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_keep_counts_names_and_foreign_files),
		cmocka_unit_test(test_keep_across_restarts),
		cmocka_unit_test(test_compression),
		cmocka_unit_test(test_bad_options),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
