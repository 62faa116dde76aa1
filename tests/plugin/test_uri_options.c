/* SPDX-License-Identifier: MIT */
/*
 * The option parser of every source and sink URI (depthao/uri.h): the
 * split of path and options, the syntax and its edge cases, each typed
 * getter, and messages that name the plugin, the key and the value.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/uri.h>

#include "common/cmocka_all.h"

static const char *const known[] = {"quality", "transport", "unit", "name", "on", NULL};

/* Parsing `text` fails with -EINVAL and a message holding `want`. */
static void expect_parse_error(const char *text, const char *want)
{
	struct dao_options *o = (struct dao_options *)(void *)&o; /* must become NULL */
	struct dao_error err;
	memset(&err, 0, sizeof err);
	assert_int_equal(dao_options_parse(&o, "rtsp", text, known, &err), -EINVAL);
	assert_null(o);
	if (!strstr(err.message, want))
		fail_msg("'%s': '%s' lacks '%s'", text, err.message, want);
}

static struct dao_options *parse_ok(const char *text)
{
	struct dao_options *o = NULL;
	struct dao_error err;
	if (dao_options_parse(&o, "rtsp", text, known, &err) != 0)
		fail_msg("'%s': %s", text ? text : "(null)", err.message);
	assert_non_null(o);
	return o;
}

static void test_path_split(void **state)
{
	(void)state;
	static const char *const bag[] = {"topic", "unit", "color", NULL};
	static const struct {
		const char *uri;
		size_t len;
	} cases[] = {
		{"a.bag", 5},
		{"", 0},
		{"?", 1},                            /* no '=': a name */
		{"a.bag?topic=/x", 5},
		{"a?b.bag?topic=/x&unit=0.001", 7},  /* a '?' in the name */
		{"a?topic=1.bag", 1},                /* the last '?' with a known key... */
		{"dir?x/a.bag?unit=1", 11},
		{"what?", 5},
		{"a.bag?tpoic=/x", 5},               /* ...else the last '?' with a '=' */
		{"a=b?c", 5},                        /* '=' before the '?' only: a name */
		{"a.bag?topic=/x?y", 5},             /* the value may hold a '?' */
		{"??topic=1", 1},
		{"?topic=1", 0},
	};
	for (size_t i = 0; i < sizeof cases / sizeof *cases; i++)
		if (dao_uri_path_len(cases[i].uri, bag) != cases[i].len)
			fail_msg("'%s': %zu, want %zu", cases[i].uri,
				 dao_uri_path_len(cases[i].uri, bag), cases[i].len);
	assert_int_equal(dao_uri_path_len("x.y4m?overwrite=true", NULL), 5);
	assert_int_equal(dao_uri_path_len("x?a=1?b", NULL), 7);
	/* the plugin prefix */
	assert_int_equal(dao_uri_prefix_len("rtsp:8554/x"), 4);
	assert_int_equal(dao_uri_prefix_len("C:\\x"), 0);
	assert_int_equal(dao_uri_prefix_len("/x:y"), 0);
}

static void test_syntax(void **state)
{
	(void)state;
	/* nothing, empty items */
	struct dao_options *o = parse_ok(NULL);
	assert_null(dao_options_value(o, "quality"));
	dao_options_free(o);
	o = parse_ok("");
	dao_options_free(o);
	o = parse_ok("&&&");
	dao_options_free(o);
	o = parse_ok("&quality=5&&transport=udp&");
	assert_string_equal(dao_options_value(o, "quality"), "5");
	assert_string_equal(dao_options_value(o, "transport"), "udp");
	assert_null(dao_options_value(o, "unit"));
	assert_null(dao_options_value(o, "nosuch"));
	assert_null(dao_options_value(NULL, "quality"));
	dao_options_free(o);
	/* the value is everything after the first '=', no percent-decoding */
	o = parse_ok("name=a=b?c%20d");
	assert_string_equal(dao_options_value(o, "name"), "a=b?c%20d");
	dao_options_free(o);
	dao_options_free(NULL);

	expect_parse_error("fsp=30", "rtsp: unknown option 'fsp' (known: quality, transport, unit, "
				     "name, on)");
	expect_parse_error("quality=5&fsp", "unknown option 'fsp'");
	expect_parse_error("quality", "rtsp: option 'quality' has no value (quality=VALUE)");
	expect_parse_error("quality=", "option 'quality' has no value");
	expect_parse_error("=5", "rtsp: an option has no name: '=5'");
	expect_parse_error("=", "an option has no name");
	expect_parse_error("quality=5&quality=6", "rtsp: option 'quality' is given twice");
	expect_parse_error("Quality=5", "unknown option 'Quality'"); /* keys are exact */
	expect_parse_error(" quality=5", "unknown option ' quality'");
	/* no list at all */
	struct dao_options *none = NULL;
	struct dao_error err;
	assert_int_equal(dao_options_parse(&none, "x", "a=1", NULL, &err), -EINVAL);
	assert_non_null(strstr(err.message, "(known: none)"));
	assert_int_equal(dao_options_parse(NULL, "x", "", known, &err), -EINVAL);
}

static void test_long_and_hostile(void **state)
{
	(void)state;
	/* a long value is kept whole; a long unknown key is cut in the message */
	size_t n = 1 << 20;
	char *text = malloc(n + 16);
	assert_non_null(text);
	memcpy(text, "name=", 5);
	memset(text + 5, 'v', n);
	text[n + 5] = '\0';
	struct dao_options *o = parse_ok(text);
	assert_int_equal(strlen(dao_options_value(o, "name")), n);
	char small[8];
	struct dao_error err;
	assert_int_equal(dao_options_get_string(o, "name", small, sizeof small, &err), -EINVAL);
	assert_non_null(strstr(err.message, "'name' must be at most 7 characters, got 1048576"));
	dao_options_free(o);
	memset(text, 'k', n);
	text[n] = '\0';
	expect_parse_error(text, "unknown option 'kkkk");
	/* a million separators */
	memset(text, '&', n);
	o = parse_ok(text);
	dao_options_free(o);
	/* every byte value but NUL, in keys and values */
	char all[600];
	size_t k = 0;
	k += (size_t)snprintf(all, sizeof all, "name=");
	for (int c = 1; c < 256; c++)
		if (c != '&')
			all[k++] = (char)c;
	all[k] = '\0';
	o = parse_ok(all);
	assert_int_equal(strlen(dao_options_value(o, "name")), 254);
	dao_options_free(o);
	expect_parse_error(all + 5, "unknown option");
	free(text);
}

static void test_int(void **state)
{
	(void)state;
	struct dao_options *o = parse_ok("quality=85&unit=-3&name=12x&on=99999999999999999999999");
	struct dao_error err;
	int64_t v = 7;
	assert_int_equal(dao_options_get_int(o, "transport", 1, 100, &v, &err), 0); /* not given */
	assert_int_equal(v, 7);
	assert_int_equal(dao_options_get_int(o, "quality", 1, 100, &v, &err), 1);
	assert_int_equal(v, 85);
	assert_int_equal(dao_options_get_int(o, "unit", -3, 0, &v, &err), 1);
	assert_int_equal(v, -3);
	v = 7;
	assert_int_equal(dao_options_get_int(o, "quality", 1, 84, &v, &err), -EINVAL);
	assert_int_equal(v, 7);
	assert_string_equal(err.message, "rtsp: 'quality' must be an integer in 1..84, got '85'");
	assert_int_equal(dao_options_get_int(o, "name", 0, 100, &v, &err), -EINVAL);
	assert_non_null(strstr(err.message, "got '12x'"));
	assert_int_equal(dao_options_get_int(o, "on", INT64_MIN, INT64_MAX, &v, &err), -EINVAL);
	dao_options_free(o);
	static const char *const bad[] = {"+5", " 5", "5 ", "0x10", "-", "1e3", "5.0"};
	for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
		char t[32];
		snprintf(t, sizeof t, "quality=%s", bad[i]);
		o = parse_ok(t);
		if (dao_options_get_int(o, "quality", -100, 10000, &v, &err) != -EINVAL)
			fail_msg("'%s' was taken for an integer", bad[i]);
		dao_options_free(o);
	}
}

static void test_double(void **state)
{
	(void)state;
	struct dao_options *o = parse_ok("unit=0.001&quality=0&name=1e-4&on=inf&transport=nan");
	struct dao_error err;
	double v = 0.5;
	assert_int_equal(dao_options_get_double(o, "unit", 0, 1, DAO_OPTIONS_MIN_EXCLUSIVE, &v, &err),
			 1);
	assert_true(v == 0.001);
	assert_int_equal(dao_options_get_double(o, "name", 0, 1, 0, &v, &err), 1);
	assert_true(v == 1e-4);
	assert_int_equal(dao_options_get_double(o, "quality", 0, 1, 0, &v, &err), 1);
	assert_true(v == 0);
	v = 0.5;
	assert_int_equal(dao_options_get_double(o, "quality", 0, 1, DAO_OPTIONS_MIN_EXCLUSIVE, &v,
						&err), -EINVAL);
	assert_true(v == 0.5);
	assert_string_equal(err.message, "rtsp: 'quality' must be a number in (0, 1], got '0'");
	assert_int_equal(dao_options_get_double(o, "unit", 0, 0.001, DAO_OPTIONS_MAX_EXCLUSIVE, &v,
						&err), -EINVAL);
	assert_non_null(strstr(err.message, "in [0, 0.001)"));
	assert_int_equal(dao_options_get_double(o, "on", -1e308, 1e308, 0, &v, &err), -EINVAL);
	assert_int_equal(dao_options_get_double(o, "transport", -1e308, 1e308, 0, &v, &err),
			 -EINVAL);
	assert_int_equal(dao_options_get_double(o, "nosuch", 0, 1, 0, &v, &err), 0);
	dao_options_free(o);
	o = parse_ok("unit= 1");
	assert_int_equal(dao_options_get_double(o, "unit", 0, 2, 0, &v, &err), -EINVAL);
	dao_options_free(o);
	o = parse_ok("unit=1x");
	assert_int_equal(dao_options_get_double(o, "unit", 0, 2, 0, &v, &err), -EINVAL);
	dao_options_free(o);
}

static void test_bool_enum_string(void **state)
{
	(void)state;
	struct dao_options *o = parse_ok("on=true&quality=0&unit=yes&transport=UDP&name=abc");
	struct dao_error err;
	int b = 5;
	assert_int_equal(dao_options_get_bool(o, "on", &b, &err), 1);
	assert_int_equal(b, 1);
	assert_int_equal(dao_options_get_bool(o, "quality", &b, &err), 1);
	assert_int_equal(b, 0);
	assert_int_equal(dao_options_get_bool(o, "unit", &b, &err), -EINVAL);
	assert_string_equal(err.message, "rtsp: 'unit' must be true or false, got 'yes'");
	assert_int_equal(b, 0);
	assert_int_equal(dao_options_get_bool(o, "nosuch", &b, &err), 0);

	static const char *const transports[] = {"tcp", "udp", NULL};
	int i = -1;
	assert_int_equal(dao_options_get_enum(o, "transport", transports, &i, &err), 1);
	assert_int_equal(i, 1); /* case is ignored */
	assert_int_equal(dao_options_get_enum(o, "name", transports, &i, &err), -EINVAL);
	assert_string_equal(err.message, "rtsp: 'name' must be one of tcp, udp, got 'abc'");
	assert_int_equal(i, 1);

	char buf[4] = "xyz";
	assert_int_equal(dao_options_get_string(o, "name", buf, sizeof buf, &err), 1);
	assert_string_equal(buf, "abc");
	assert_int_equal(dao_options_get_string(o, "name", buf, 3, &err), -EINVAL);
	assert_string_equal(err.message, "rtsp: 'name' must be at most 2 characters, got 3");
	assert_int_equal(dao_options_get_string(o, "nosuch", buf, sizeof buf, &err), 0);
	assert_string_equal(buf, "abc");
	dao_options_free(o);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_path_split),
		cmocka_unit_test(test_syntax),
		cmocka_unit_test(test_long_and_hostile),
		cmocka_unit_test(test_int),
		cmocka_unit_test(test_double),
		cmocka_unit_test(test_bool_enum_string),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
