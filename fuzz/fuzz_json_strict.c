/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target for the strict JSON check of the http and foxglove sinks
 * (plugins/common/json_strict.c, compiled here with instrumentation).  The
 * input is the text a client sends, as is.  Aborts if:
 *  - a refusal has no reason, or its "at byte N" lies past the input;
 *  - an accepted text holds a NUL byte or bytes that are not UTF-8, or json-c
 *    (the parser the sinks use next) does not parse all of it, or json-c's own
 *    rendering of what it parsed is refused (a writer and a reader that agree);
 *  - the depth limit is not monotonic (accepted nested at most 2 deep but refused
 *    at 16, or the other way round).
 */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <json-c/json.h>

#include "json_strict.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define DEPTH 16

static void check_reason(int r, const char *why, size_t size)
{
	if (r == 0)
		return;
	const char *at = strstr(why, " at byte ");
	if (r != -EINVAL || !at || at == why || strtoull(at + 9, NULL, 10) > size)
		abort();
}

static void check_accepted(const char *text, size_t size)
{
	const unsigned char *p = (const unsigned char *)text, *end = p + size;
	while (p < end) {
		size_t n = json_utf8_len(p, end);
		if (!n || !*p)
			abort();
		p += n;
	}
	struct json_tokener *tk = json_tokener_new_ex(DEPTH + 2);
	if (!tk)
		return;
	struct json_object *j = json_tokener_parse_ex(tk, text, (int)size);
	enum json_tokener_error e = json_tokener_get_error(tk);
	if (e == json_tokener_continue) /* a bare number is complete only at the end */
		j = json_tokener_parse_ex(tk, "", 1), e = json_tokener_get_error(tk);
	if (e != json_tokener_success)
		abort();
	/* json-c escapes '/' unless told not to, in keys too; it writes a double
	   past DBL_MAX ("1e400") as Infinity, which is not JSON: not its text then */
	const char *again = json_object_to_json_string_ext(
		j, JSON_C_TO_STRING_PLAIN | JSON_C_TO_STRING_NOSLASHESCAPE);
	char why[160];
	if (!strstr(again, "Infinity") && !strstr(again, "NaN") &&
	    json_strict_check(again, strlen(again), DEPTH, why, sizeof why) != 0)
		abort();
	json_object_put(j);
	json_tokener_free(tk);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size > 65536)
		return 0;
	char *text = malloc(size ? size : 1); /* exact size: ASan sees a read past it */
	if (!text)
		return 0;
	memcpy(text, data, size);
	char why[160] = "", why2[160] = "";
	int r = json_strict_check(text, size, DEPTH, why, sizeof why);
	check_reason(r, why, size);
	int r2 = json_strict_check(text, size, 2, why2, sizeof why2);
	check_reason(r2, why2, size);
	if ((r2 == 0 && r != 0) || (r == 0 && r2 != 0 && !strstr(why2, "nested too deeply")))
		abort();
	if (r == 0)
		check_accepted(text, size);
	free(text);
	return 0;
}
