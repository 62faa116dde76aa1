/* SPDX-License-Identifier: MIT */
/*
 * The option strings of source and sink URIs ("KEY=VALUE&KEY=VALUE"), for
 * every plugin: one syntax, typed getters, and messages that name the
 * plugin, the key and the value (depthao/uri.h).  Parsed once, when a
 * plugin opens: the options are copied into one allocation and split in
 * place.
 */
#include <depthao/uri.h>

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/error_internal.h"

struct dao_option {
	const char *key, *value;
};

struct dao_options {
	char who[32];
	size_t count;
	struct dao_option *items; /* into text */
	char *text;
};

/* `key` of `n` bytes is one of `known`. */
static int is_known(const char *const *known, const char *key, size_t n)
{
	for (size_t i = 0; known && known[i]; i++)
		if (strlen(known[i]) == n && !memcmp(known[i], key, n))
			return 1;
	return 0;
}

/* `s` starts with one of the `known` keys and '='. */
static int starts_with_known(const char *const *known, const char *s)
{
	for (size_t i = 0; known && known[i]; i++) {
		size_t n = strlen(known[i]);
		if (!strncmp(s, known[i], n) && s[n] == '=')
			return 1;
	}
	return 0;
}

size_t dao_uri_path_len(const char *uri, const char *const *known)
{
	size_t len = strlen(uri);
	for (size_t i = len; i-- > 0;)
		if (uri[i] == '?' && starts_with_known(known, uri + i + 1))
			return i;
	const char *last = strrchr(uri, '?');
	return last && strchr(last, '=') ? (size_t)(last - uri) : len;
}

/* "a, b, c" of a NULL-terminated list, cut to fit. */
static void list_names(const char *const *names, char *buf, size_t cap)
{
	size_t used = 0;
	buf[0] = '\0';
	for (size_t i = 0; names && names[i] && used < cap; i++)
		used += (size_t)snprintf(buf + used, cap - used, "%s%s", i ? ", " : "", names[i]);
}

/* Checks one "key=value" item (NUL-terminated, in place) and splits it into `it`. */
static int parse_item(const struct dao_options *o, char *kv, const char *const *known,
		      struct dao_option *it, struct dao_error *err)
{
	char *eq = strchr(kv, '=');
	if (eq == kv)
		return dao_error_set(err, -EINVAL, "%s: an option has no name: '%.80s'", o->who, kv);
	size_t n = eq ? (size_t)(eq - kv) : strlen(kv);
	if (!is_known(known, kv, n)) {
		char list[256];
		list_names(known, list, sizeof list);
		return dao_error_set(err, -EINVAL, "%s: unknown option '%.*s' (known: %s)", o->who,
				     (int)(n > 80 ? 80 : n), kv, list[0] ? list : "none");
	}
	if (!eq || !eq[1])
		return dao_error_set(err, -EINVAL, "%s: option '%.*s' has no value (%.*s=VALUE)",
				     o->who, (int)n, kv, (int)n, kv);
	*eq = '\0';
	for (size_t i = 0; i < o->count; i++)
		if (!strcmp(o->items[i].key, kv))
			return dao_error_set(err, -EINVAL, "%s: option '%s' is given twice", o->who,
					     kv);
	it->key = kv;
	it->value = eq + 1;
	return 0;
}

int dao_options_parse(struct dao_options **out, const char *who, const char *text,
		      const char *const *known, struct dao_error *err)
{
	if (!out)
		return dao_error_set(err, -EINVAL, "dao_options_parse: no place for the result");
	*out = NULL;
	if (!text)
		text = "";
	size_t len = strlen(text), items = 1;
	for (const char *p = text; (p = strchr(p, '&')); p++)
		items++;
	struct dao_options *o = calloc(1, sizeof *o);
	if (!o || !(o->items = calloc(items, sizeof *o->items)) || !(o->text = malloc(len + 1))) {
		dao_options_free(o);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	snprintf(o->who, sizeof o->who, "%s", who ? who : "options");
	memcpy(o->text, text, len + 1);
	for (char *kv = o->text, *next; kv; kv = next) {
		next = strchr(kv, '&');
		if (next)
			*next++ = '\0';
		if (!*kv)
			continue; /* "&&", a leading or trailing '&' */
		int r = parse_item(o, kv, known, &o->items[o->count], err);
		if (r < 0) {
			dao_options_free(o);
			return r;
		}
		o->count++;
	}
	*out = o;
	return 0;
}

void dao_options_free(struct dao_options *o)
{
	if (!o)
		return;
	free(o->items);
	free(o->text);
	free(o);
}

const char *dao_options_value(const struct dao_options *o, const char *key)
{
	for (size_t i = 0; o && key && i < o->count; i++)
		if (!strcmp(o->items[i].key, key))
			return o->items[i].value;
	return NULL;
}

int dao_options_get_string(const struct dao_options *o, const char *key, char *buf, size_t cap,
			   struct dao_error *err)
{
	const char *v = dao_options_value(o, key);
	if (!v)
		return 0;
	size_t n = strlen(v);
	if (!buf || n >= cap)
		return dao_error_set(err, -EINVAL, "%s: '%s' must be at most %zu characters, got %zu",
				     o->who, key, cap ? cap - 1 : 0, n);
	memcpy(buf, v, n + 1);
	return 1;
}

int dao_options_get_int(const struct dao_options *o, const char *key, int64_t min, int64_t max,
			int64_t *value, struct dao_error *err)
{
	const char *v = dao_options_value(o, key);
	if (!v)
		return 0;
	const char *d = v + (*v == '-');
	int ok = *d >= '0' && *d <= '9';
	char *end = NULL;
	errno = 0;
	long long n = ok ? strtoll(v, &end, 10) : 0;
	if (!ok || *end || errno || n < min || n > max)
		return dao_error_set(err, -EINVAL,
				     "%s: '%s' must be an integer in %" PRId64 "..%" PRId64
				     ", got '%.80s'", o->who, key, min, max, v);
	*value = n;
	return 1;
}

int dao_options_get_double(const struct dao_options *o, const char *key, double min, double max,
			   unsigned flags, double *value, struct dao_error *err)
{
	const char *v = dao_options_value(o, key);
	if (!v)
		return 0;
	char *end;
	double x = strtod(v, &end);
	int lo_ok = flags & DAO_OPTIONS_MIN_EXCLUSIVE ? x > min : x >= min;
	int hi_ok = flags & DAO_OPTIONS_MAX_EXCLUSIVE ? x < max : x <= max;
	/* strtod skips leading space: the value must start as a number does */
	int starts = (*v >= '0' && *v <= '9') || *v == '-' || *v == '+' || *v == '.';
	if (!starts || *end || !isfinite(x) || !lo_ok || !hi_ok)
		return dao_error_set(err, -EINVAL, "%s: '%s' must be a number in %c%g, %g%c, got "
				     "'%.80s'", o->who, key,
				     flags & DAO_OPTIONS_MIN_EXCLUSIVE ? '(' : '[', min, max,
				     flags & DAO_OPTIONS_MAX_EXCLUSIVE ? ')' : ']', v);
	*value = x;
	return 1;
}

int dao_options_get_bool(const struct dao_options *o, const char *key, int *value,
			 struct dao_error *err)
{
	const char *v = dao_options_value(o, key);
	if (!v)
		return 0;
	if (!strcmp(v, "true") || !strcmp(v, "1"))
		*value = 1;
	else if (!strcmp(v, "false") || !strcmp(v, "0"))
		*value = 0;
	else
		return dao_error_set(err, -EINVAL, "%s: '%s' must be true or false, got '%.80s'",
				     o->who, key, v);
	return 1;
}

int dao_options_get_enum(const struct dao_options *o, const char *key, const char *const *names,
			 int *index, struct dao_error *err)
{
	const char *v = dao_options_value(o, key);
	if (!v)
		return 0;
	for (int i = 0; names && names[i]; i++)
		if (!strcasecmp(names[i], v)) {
			*index = i;
			return 1;
		}
	char list[256];
	list_names(names, list, sizeof list);
	return dao_error_set(err, -EINVAL, "%s: '%s' must be one of %s, got '%.80s'", o->who, key,
			     list, v);
}
