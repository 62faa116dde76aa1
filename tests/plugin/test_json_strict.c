/* SPDX-License-Identifier: MIT */
/*
 * The strict JSON check the http and foxglove sinks run on what clients send
 * (plugins/common/json_strict.h): each rule of its grammar on the smallest text
 * that breaks it (NUL raw and escaped, bytes that are not UTF-8, overlong forms,
 * encoded and escaped surrogates, duplicate keys, escapes in keys, the depth
 * limit on both sides, text after the value, numbers and literals), the byte
 * offset it reports, and texts written by json-c from random objects, which
 * must all pass (an independent writer).
 */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <json-c/json.h>

#include "common/cmocka_all.h"
#include "json_strict.h"

#define DEPTH 16

static void ok_n(const char *t, size_t n)
{
	char why[160] = "";
	if (json_strict_check(t, n, DEPTH, why, sizeof why) != 0)
		fail_msg("refused %.*s: %s", (int)n, t, why);
}

static void ok(const char *t)
{
	ok_n(t, strlen(t));
}

/* Refused with a reason holding `want`, "at byte `at`". */
static void bad_n(const char *t, size_t n, const char *want, size_t at)
{
	char why[160] = "", where[32];
	if (json_strict_check(t, n, DEPTH, why, sizeof why) != -EINVAL)
		fail_msg("accepted %.*s", (int)n, t);
	snprintf(where, sizeof where, " at byte %zu", at);
	const size_t wl = strlen(why), hl = strlen(where);
	if (!strstr(why, want) || wl < hl || strcmp(why + wl - hl, where))
		fail_msg("%.*s: '%s' lacks '%s'%s", (int)n, t, why, want, where);
	for (const char *c = why; *c; c++) /* plain ASCII, never the input */
		assert_true(*c >= 0x20 && *c < 0x7f);
}

static void bad(const char *t, const char *want, size_t at)
{
	bad_n(t, strlen(t), want, at);
}

static void test_nul(void **state)
{
	(void)state;
	bad_n("\"a\0b\"", 5, "NUL", 2);
	bad_n("{\"a\":1}\0", 8, "NUL byte after the value", 7);
	bad_n("\0", 1, "NUL", 0);
	bad("\"hbao\\u0000junk\"", "\\u0000", 5);
	bad("{\"radius\\u0000x\":0.77}", "escape inside a key (\\u0000, a NUL)", 8);
	bad_n("{\"ra\0\":1}", 9, "NUL", 4);
}

static void test_utf8(void **state)
{
	(void)state;
	ok("\"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80 \xf4\x8f\xbf\xbf\""); /* up to U+10FFFF */
	bad("\"\xff\"", "not UTF-8", 1);
	bad("\"a\x80\"", "not UTF-8", 2);            /* a lone continuation byte */
	bad("\"\xc3\"", "not UTF-8", 1);             /* cut short by the quote */
	bad("\"\xc3", "not UTF-8", 1);               /* cut short by the end */
	bad("\"\xc0\xaf\"", "not UTF-8", 1);         /* overlong '/' */
	bad("\"\xc1\xbf\"", "not UTF-8", 1);
	bad("\"\xe0\x80\xaf\"", "not UTF-8", 1);     /* overlong, 3 bytes */
	bad("\"\xf0\x80\x80\xaf\"", "not UTF-8", 1); /* overlong, 4 bytes */
	bad("\"\xed\xa0\x80\"", "not UTF-8", 1);     /* U+D800 encoded */
	bad("\"\xed\xbf\xbf\"", "not UTF-8", 1);     /* U+DFFF encoded */
	bad("\"\xf4\x90\x80\x80\"", "not UTF-8", 1); /* past U+10FFFF */
	bad("\"\xf5\x80\x80\x80\"", "not UTF-8", 1);
	bad("{\"k\xff\":1}", "not UTF-8", 3);
	bad("\xff", "not UTF-8", 0);
	bad("[1,\xc3\xa9]", "unexpected character", 3); /* UTF-8, but not a value */
}

static void test_surrogates(void **state)
{
	(void)state;
	ok("\"\\ud83d\\ude00\"");
	ok("\"\\uD83D\\uDE00\\u00e9\\uFFFF\"");
	bad("\"\\ud83d\"", "unpaired surrogate", 1);
	bad("\"\\ud83dx\"", "unpaired surrogate", 1);
	bad("\"\\ud83d\\u0041\"", "unpaired surrogate", 1);
	bad("\"\\ud83d\\ud83d\"", "unpaired surrogate", 1);
	bad("\"ab\\ude00\"", "unpaired surrogate", 3);
	bad("\"\\u12\"", "invalid \\u escape", 1);
	bad("\"\\u12g4\"", "invalid \\u escape", 1);
	bad("\"\\x41\"", "invalid escape", 1);
	bad("\"\\", "does not end", 1);
	ok("\"\\\"\\\\\\/\\b\\f\\n\\r\\t\"");
}

static void test_keys(void **state)
{
	(void)state;
	ok("{\"a\":1,\"b\":{\"a\":2},\"c\":[{\"a\":3},{\"a\":4}]}"); /* same key, other objects */
	bad("{\"a\":1,\"a\":2}", "duplicate key", 7);
	bad("{\"a\":1,\"b\":{\"x\":1,\"y\":2,\"x\":3},\"c\":0}", "duplicate key", 24);
	bad("{\"a\":{\"b\":1},\"a\":2}", "duplicate key", 13);
	bad("{\"\\u0061\":1}", "escape inside a key", 2); /* "a" spelled another way */
	bad("{\"a\":1,\"\\u0061\":2}", "escape inside a key", 8);
	bad("{\"a\\\"b\":1}", "escape inside a key", 3);
	ok("{\"\xc3\xa9\":1,\"e\xcc\x81\":2}"); /* é precomposed and combined: two keys */
	ok("{\"\":1}");
	bad("{\"\":1,\"\":2}", "duplicate key", 6);
	bad("{1:2}", "expected a key", 1);
	bad("{\"a\" 1}", "expected ':'", 5);
	bad("{\"a\":1,}", "expected a key", 7);
	bad("{\"a\":1", "expected ',' or '}'", 6);
	/* JSON_STRICT_MAX_KEYS keys at once in one object, then one more */
	char big[JSON_STRICT_MAX_KEYS * 12 + 16];
	size_t n = 0;
	big[n++] = '{';
	for (int i = 0; i <= JSON_STRICT_MAX_KEYS; i++)
		n += (size_t)snprintf(big + n, sizeof big - n, "%s\"k%d\":0", i ? "," : "", i);
	big[n++] = '}';
	bad_n(big, n, "too many keys", n - 1 - strlen("\"k512\":0"));
	const size_t last = n - 1 - strlen(",\"k512\":0");
	big[last] = '}';
	ok_n(big, last + 1);
}

/* `n` arrays or objects nested, around 1 */
static size_t nest(char *b, int n, int objects)
{
	size_t o = 0;
	for (int i = 0; i < n; i++)
		o += (size_t)sprintf(b + o, "%s", objects ? "{\"k\":" : "[");
	b[o++] = '1';
	for (int i = 0; i < n; i++)
		b[o++] = objects ? '}' : ']';
	b[o] = '\0';
	return o;
}

static void test_depth(void **state)
{
	(void)state;
	char b[256], why[160];
	for (int objects = 0; objects < 2; objects++) {
		size_t n = nest(b, DEPTH, objects);
		ok_n(b, n);
		n = nest(b, DEPTH + 1, objects);
		bad_n(b, n, "nested too deeply", (size_t)DEPTH * (objects ? 5 : 1));
	}
	/* the limit is the caller's: 0 admits scalars only, 1 one level */
	assert_int_equal(json_strict_check("1", 1, 0, why, sizeof why), 0);
	assert_int_equal(json_strict_check("[]", 2, 0, why, sizeof why), -EINVAL);
	assert_int_equal(json_strict_check("[1]", 3, 1, why, sizeof why), 0);
	assert_int_equal(json_strict_check("[[]]", 4, 1, why, sizeof why), -EINVAL);
	assert_int_equal(json_strict_check("[[]]", 4, 2, why, sizeof why), 0);
	/* deep nesting costs no more than the limit: 100000 '[' refused at the limit */
	char *deep = malloc(100000);
	assert_non_null(deep);
	memset(deep, '[', 100000);
	assert_int_equal(json_strict_check(deep, 100000, 32, why, sizeof why), -EINVAL);
	assert_non_null(strstr(why, "nested too deeply at byte 32"));
	free(deep);
}

static void test_after_value(void **state)
{
	(void)state;
	ok(" \t\r\n{\"a\":[1, 2 ,3]} \n");
	bad("{} {}", "text after the value", 3);
	bad("1 2", "text after the value", 2);
	bad("{}x", "text after the value", 2);
	bad("\"a\"\"b\"", "text after the value", 3);
	bad("", "expected a value", 0);
	bad("   ", "expected a value", 3);
	bad("[1,]", "unexpected character", 3);
	bad("[1 2]", "expected ',' or ']'", 3);
	bad("[", "expected a value", 1);
	bad("\f1", "unexpected character", 0); /* form feed is not JSON whitespace */
	char why[8];
	assert_int_equal(json_strict_check(NULL, 0, DEPTH, why, sizeof why), -EINVAL);
	assert_int_equal(json_strict_check("1", 1, DEPTH, NULL, 0), 0);
	assert_int_equal(json_strict_check("x", 1, DEPTH, NULL, 0), -EINVAL);
	assert_int_equal(json_strict_check("x", 1, DEPTH, why, sizeof why), -EINVAL);
	assert_int_equal(strlen(why), sizeof why - 1); /* cut, terminated */
}

static void test_numbers_literals(void **state)
{
	(void)state;
	static const char *const good[] = {"0", "-0", "1", "-1", "10", "0.5", "-0.5e-3", "1E5",
					   "1e+5", "123456789012345678901234567890", "1.0e308",
					   "true", "false", "null", "[true,false,null]"};
	for (size_t i = 0; i < sizeof good / sizeof good[0]; i++)
		ok(good[i]);
	bad("01", "text after the value", 1);
	bad("-", "malformed number", 1);
	bad("-a", "malformed number", 1);
	bad("+1", "unexpected character", 0);
	bad(".5", "unexpected character", 0);
	bad("1.", "malformed number", 2);
	bad("1.e5", "malformed number", 2);
	bad("1e", "malformed number", 2);
	bad("1e+", "malformed number", 3);
	bad("0x10", "text after the value", 1);
	bad("NaN", "unexpected character", 0);
	bad("Infinity", "unexpected character", 0);
	bad("-Infinity", "malformed number", 1);
	bad("tru", "unexpected character", 0);
	bad("True", "unexpected character", 0);
	bad("nul", "unexpected character", 0);
	bad("truex", "text after the value", 4);
	bad("[1,2e]", "malformed number", 5);
}

static uint32_t rng(uint32_t *s)
{
	*s = *s * 1664525u + 1013904223u;
	return *s >> 8;
}

/* A random string: ASCII (control characters too), 2-, 3- and 4-byte UTF-8. */
static void random_text(uint32_t *seed, char *b, size_t cap, int key)
{
	size_t o = 0, n = rng(seed) % 12;
	static const char *const multi[] = {"\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x98\x80",
					    "\xef\xbf\xbf", "\xf4\x8f\xbf\xbf"};
	for (size_t i = 0; i < n && o + 5 < cap; i++) {
		uint32_t r = rng(seed) % 10;
		if (r < 6) { /* keys: no character json-c would escape */
			char c = (char)(key ? 'a' + rng(seed) % 26 : 1 + rng(seed) % 127);
			b[o++] = c;
		} else {
			const char *m = multi[rng(seed) % 5];
			memcpy(b + o, m, strlen(m));
			o += strlen(m);
		}
	}
	b[o] = '\0';
}

static struct json_object *random_value(uint32_t *seed, int depth)
{
	char t[64];
	uint32_t kind = rng(seed) % (depth < DEPTH ? 8 : 6);
	switch (kind) {
	case 0: return json_object_new_int64((int64_t)rng(seed) - (1 << 23));
	case 1: return json_object_new_double((double)rng(seed) / 7.0 * (rng(seed) % 2 ? 1e-30 : 1e30));
	case 2: return json_object_new_boolean((int)(rng(seed) % 2));
	case 3: return NULL; /* null */
	case 4:
	case 5: random_text(seed, t, sizeof t, 0); return json_object_new_string(t);
	case 6: {
		struct json_object *a = json_object_new_array();
		for (uint32_t i = rng(seed) % 5; i; i--)
			json_object_array_add(a, random_value(seed, depth + 1));
		return a;
	}
	default: {
		struct json_object *o = json_object_new_object();
		for (uint32_t i = rng(seed) % 5; i; i--) {
			random_text(seed, t, sizeof t, 1);
			json_object_object_add(o, t, random_value(seed, depth + 1)); /* json-c: last wins */
		}
		return o;
	}
	}
}

static void test_json_c_written(void **state)
{
	(void)state;
	uint32_t seed = 38;
	for (int i = 0; i < 3000; i++) {
		struct json_object *j = random_value(&seed, 0);
		const int flags[] = {JSON_C_TO_STRING_PLAIN, JSON_C_TO_STRING_PRETTY,
				     JSON_C_TO_STRING_SPACED | JSON_C_TO_STRING_NOSLASHESCAPE};
		const char *t = json_object_to_json_string_ext(j, flags[i % 3]);
		ok(t);
		json_object_put(j);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_nul),
		cmocka_unit_test(test_utf8),
		cmocka_unit_test(test_surrogates),
		cmocka_unit_test(test_keys),
		cmocka_unit_test(test_depth),
		cmocka_unit_test(test_after_value),
		cmocka_unit_test(test_numbers_literals),
		cmocka_unit_test(test_json_c_written),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
