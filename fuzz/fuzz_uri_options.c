/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target for the URI option parser (src/plugin/uri_options.c,
 * depthao/uri.h).  The input, cut at its first NUL, is a whole URI: it is
 * split with dao_uri_path_len() and its options parsed and read with every
 * getter, as a plugin does.  Aborts if the split is out of the string, if a
 * failure has no message or another code than -EINVAL, or if a value read
 * back is outside the range asked for.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/uri.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *const known[] = {"topic", "unit", "quality", "transport", "overwrite", "name",
				    NULL};

static void check(int r, int allow_zero, const struct dao_error *err)
{
	if (r < 0 && (r != -EINVAL || !err->message[0]))
		abort();
	if (r == 0 && !allow_zero)
		abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char *uri = malloc(size + 1);
	if (!uri)
		return 0;
	memcpy(uri, data, size);
	uri[size] = '\0'; /* the input up to its first NUL, as a C string */
	size_t len = strlen(uri);
	size_t at = dao_uri_path_len(uri, known);
	if (at > len || (at < len && uri[at] != '?'))
		abort();
	if (dao_uri_path_len(uri, NULL) > len)
		abort();
	struct dao_options *o = NULL;
	struct dao_error err;
	memset(&err, 0, sizeof err);
	int r = dao_options_parse(&o, "fuzz", at < len ? uri + at + 1 : NULL, known, &err);
	check(r, 1, &err);
	if (r == 0) {
		if (!o)
			abort();
		int64_t i = 0;
		double d = 0;
		int b = -1, e = -1;
		char buf[16];
		static const char *const names[] = {"tcp", "udp", NULL};
		err.message[0] = '\0';
		r = dao_options_get_int(o, "quality", -5, 100, &i, &err);
		check(r, 1, &err);
		if (r > 0 && (i < -5 || i > 100))
			abort();
		err.message[0] = '\0';
		r = dao_options_get_double(o, "unit", 0, 1, DAO_OPTIONS_MIN_EXCLUSIVE, &d, &err);
		check(r, 1, &err);
		if (r > 0 && !(isfinite(d) && d > 0 && d <= 1))
			abort();
		err.message[0] = '\0';
		r = dao_options_get_bool(o, "overwrite", &b, &err);
		check(r, 1, &err);
		if (r > 0 && b != 0 && b != 1)
			abort();
		err.message[0] = '\0';
		r = dao_options_get_enum(o, "transport", names, &e, &err);
		check(r, 1, &err);
		if (r > 0 && e != 0 && e != 1)
			abort();
		err.message[0] = '\0';
		r = dao_options_get_string(o, "name", buf, sizeof buf, &err);
		check(r, 1, &err);
		if (r > 0 && strlen(buf) >= sizeof buf)
			abort();
		const char *v = dao_options_value(o, "topic");
		if (v && (!*v || strchr(v, '&')))
			abort(); /* values are never empty and never hold the separator */
	} else if (o) {
		abort();
	}
	dao_options_free(o);
	free(uri);
	return 0;
}
