/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

static void test_strerror(void **state)
{
	(void)state;
	assert_string_equal(dao_strerror(0), "success");
	assert_string_equal(dao_strerror(-EINVAL), "invalid argument");
	assert_string_equal(dao_strerror(-ENOMEM), "out of memory");
	assert_string_equal(dao_strerror(-ENODEV), "no such device");
	assert_string_equal(dao_strerror(-12345), "unknown error");
}

static void test_formats(void **state)
{
	(void)state;
	assert_int_equal(dao_pixfmt_bytes_per_pixel(DAO_PIXFMT_DEPTH16), 2);
	assert_int_equal(dao_pixfmt_bytes_per_pixel(DAO_PIXFMT_DEPTH_F32), 4);
	assert_int_equal(dao_pixfmt_bytes_per_pixel(DAO_PIXFMT_RGB24), 3);
	assert_int_equal(dao_pixfmt_bytes_per_pixel(DAO_PIXFMT_NORMAL_F32), 12);
	assert_int_equal(dao_pixfmt_bytes_per_pixel(DAO_PIXFMT_NONE), 0);
	assert_int_equal(dao_pixfmt_bytes_per_pixel((enum dao_pixfmt)99), 0);
	assert_string_equal(dao_pixfmt_name(DAO_PIXFMT_GRAY16), "gray16");
	assert_string_equal(dao_pixfmt_name((enum dao_pixfmt)99), "invalid");
}

/* Each broken frame fails with -EINVAL and a message that names the frame. */
static void expect_bad(const struct dao_frame *f, uint32_t w, uint32_t h, const char *needle)
{
	struct dao_error err = { 0 };
	assert_int_equal(dao_frame_check(f, "the test frame", w, h, &err), -EINVAL);
	assert_int_equal(err.code, -EINVAL);
	assert_non_null(strstr(err.message, "the test frame"));
	if (needle && !strstr(err.message, needle))
		fail_msg("message '%s' lacks '%s'", err.message, needle);
}

static void test_check(void **state)
{
	(void)state;
	uint16_t px[64];
	struct dao_frame ok = { .format = DAO_PIXFMT_DEPTH16, .width = 8, .height = 4, .stride = 16,
				.data = px };
	assert_int_equal(dao_frame_check(&ok, "x", 8, 4, NULL), 0);
	assert_int_equal(dao_frame_check(&ok, "x", 0, 0, NULL), 0);
	expect_bad(NULL, 0, 0, "NULL");
	struct dao_frame f = ok;
	f.data = NULL;
	expect_bad(&f, 0, 0, "NULL");
	f = ok;
	f.format = (enum dao_pixfmt)42;
	expect_bad(&f, 0, 0, "format");
	f = ok;
	f.width = 0;
	expect_bad(&f, 0, 0, "size");
	f = ok;
	f.height = DAO_MAX_DIMENSION + 1;
	expect_bad(&f, 0, 0, "size");
	f = ok;
	f.stride = 15;
	expect_bad(&f, 0, 0, "stride");
	f.stride = -16;
	expect_bad(&f, 0, 0, "stride");
	expect_bad(&ok, 8, 5, "does not match");
	expect_bad(&ok, 9, 4, "does not match");
}

static void test_alloc(void **state)
{
	(void)state;
	struct dao_frame f;
	struct dao_error err;
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_RGB24, 7, 3, &err), 0);
	assert_int_equal(f.stride, 21);
	assert_int_equal(f.width, 7);
	for (int i = 0; i < 21 * 3; i++)
		assert_int_equal(((unsigned char *)f.data)[i], 0);
	assert_int_equal(dao_frame_check(&f, "alloc", 7, 3, NULL), 0);
	dao_frame_free(&f);
	assert_null(f.data);
	dao_frame_free(&f);   /* twice is harmless */
	dao_frame_free(NULL);
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_NONE, 7, 3, &err), -EINVAL);
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_GRAY8, 0, 3, &err), -EINVAL);
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_GRAY8, 3, DAO_MAX_DIMENSION + 1, &err), -EINVAL);
	assert_non_null(strstr(err.message, "out of range"));
	assert_int_equal(dao_frame_alloc(NULL, DAO_PIXFMT_GRAY8, 3, 3, &err), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_strerror),
		cmocka_unit_test(test_formats),
		cmocka_unit_test(test_check),
		cmocka_unit_test(test_alloc),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
