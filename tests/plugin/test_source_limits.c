/* SPDX-License-Identifier: MIT */
/*
 * dao_source_open_limited(): the built-in "oni" and "images" sources refuse
 * files whose depth images are larger than the limit (width x height) with
 * -EFBIG; plugin sources are checked on the size they report after open;
 * dao_source_open() applies DAO_DEFAULT_MAX_PIXELS.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "common/test_common.h"
#include "source_test_util.h"

static char g_oni[512], g_dir[512];

static int setup(void **state)
{
	(void)state;
	const char *tmp = dao_test_tmpdir("source-limits");
	snprintf(g_oni, sizeof g_oni, "%s/three.oni", tmp);
	snprintf(g_dir, sizeof g_dir, "%s/pngs", tmp);
	if (test_write_oni(g_oni, 3, DAO_ONI_CODEC_16Z) < 0 || (mkdir(g_dir, 0777) && errno != EEXIST))
		return -1;
	char png[600];
	snprintf(png, sizeof png, "%s/0001.png", g_dir);
	struct dao_frame f;
	struct dao_error err;
	if (dao_frame_alloc(&f, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, &err) < 0)
		return -1;
	int r = dao_png_write(png, &f, &err);
	dao_frame_free(&f);
	return r;
}

/* Opens `uri` with `limit`; returns the code, closing what opened. */
static int try_open(const struct dao_plugins *p, const char *uri, uint64_t limit,
		    struct dao_error *err)
{
	struct dao_source *s = NULL;
	memset(err, 0, sizeof(*err));
	int r = dao_source_open_limited(p, uri, NULL, limit, &s, err);
	if (r == 0) {
		struct dao_source_info in;
		dao_source_get_info(s, &in);
		assert_true((uint64_t)in.width * in.height <= (limit ? limit : DAO_DEFAULT_MAX_PIXELS));
		dao_source_close(s);
	} else {
		assert_null(s);
	}
	return r;
}

static void test_builtin_sources(void **state)
{
	(void)state;
	struct dao_plugins *p;
	struct dao_error err;
	char uri[600];
	assert_int_equal(dao_plugins_load(&p, "", &err), 0);
	const uint64_t n = (uint64_t)TEST_W * TEST_H; /* 37 x 23 = 851 */

	assert_int_equal(try_open(p, g_oni, n - 1, &err), -EFBIG);
	assert_non_null(strstr(err.message, "is 37x23 (851 pixels), more than the limit of 850 pixels"));
	assert_int_equal(try_open(p, g_oni, n, &err), 0);
	assert_int_equal(try_open(p, g_oni, 0, &err), 0);

	snprintf(uri, sizeof uri, "images:%s", g_dir);
	assert_int_equal(try_open(p, uri, n - 1, &err), -EFBIG);
	assert_non_null(strstr(err.message, "0001.png' is 37x23 (851 pixels), more than the limit of 850"));
	assert_int_equal(try_open(p, uri, n, &err), 0);
	dao_plugins_free(p);
}

static void test_plugin_source_checked_after_open(void **state)
{
	(void)state;
	const char *dir = getenv("DAO_FAKE_PLUGIN_DIR");
	if (!dir)
		skip();
	struct dao_plugins *p;
	struct dao_error err;
	struct dao_source *s = NULL;
	assert_int_equal(dao_plugins_load(&p, dir, &err), 0);
	/* 5000 x 4000 is over the default of 4096 x 4096, through either function */
	assert_int_equal(dao_source_open(p, "fakebig:5000x4000", NULL, &s, &err), -EFBIG);
	assert_null(s);
	assert_non_null(strstr(err.message, "source 'fakebig' delivers 5000x4000 depth images "
					    "(20000000 pixels), more than the limit of 16777216"));
	assert_int_equal(try_open(p, "fakebig:5000x4000", 0, &err), -EFBIG);
	assert_int_equal(try_open(p, "fakebig:5000x4000", 20000000, &err), 0);
	assert_int_equal(try_open(p, "fakebig:640x480", 640 * 480 - 1, &err), -EFBIG);
	assert_int_equal(dao_source_open(p, "fakebig:640x480", NULL, &s, &err), 0);
	dao_source_close(s);
	dao_plugins_free(p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_builtin_sources),
		cmocka_unit_test(test_plugin_source_checked_after_open),
	};
	return cmocka_run_group_tests(tests, setup, NULL);
}
