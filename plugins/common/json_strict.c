/* SPDX-License-Identifier: MIT */
/* The strict JSON check of json_strict.h: a recursive-descent recogniser that
   allocates nothing (the keys of the open objects are spans of the input). */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "json_strict.h"

struct key {
	const unsigned char *at;
	size_t len;
};

struct scan {
	const unsigned char *p, *end, *start;
	int max_depth;
	const char *err;
	size_t err_at;
	/* the keys of the objects being read, one stack: an object's from its base up */
	struct key keys[JSON_STRICT_MAX_KEYS];
	size_t nkeys;
};

static int fail(struct scan *s, const char *msg)
{
	if (!s->err) {
		s->err = msg;
		s->err_at = (size_t)(s->p - s->start);
	}
	return -1;
}

static void skip_ws(struct scan *s)
{
	while (s->p < s->end && (*s->p == ' ' || *s->p == '\t' || *s->p == '\n' || *s->p == '\r'))
		s->p++;
}

size_t json_utf8_len(const unsigned char *p, const unsigned char *end)
{
	const unsigned c = p[0];
	size_t n;
	uint32_t cp, min;
	if (c < 0x80)
		return 1;
	if (c >= 0xc2 && c <= 0xdf)
		n = 2, cp = c & 0x1f, min = 0x80;
	else if (c >= 0xe0 && c <= 0xef)
		n = 3, cp = c & 0x0f, min = 0x800;
	else if (c >= 0xf0 && c <= 0xf4)
		n = 4, cp = c & 0x07, min = 0x10000;
	else
		return 0; /* a continuation byte, an overlong lead (c0, c1) or past U+10FFFF */
	if ((size_t)(end - p) < n)
		return 0;
	for (size_t i = 1; i < n; i++) {
		if ((p[i] & 0xc0) != 0x80)
			return 0;
		cp = cp << 6 | (p[i] & 0x3f);
	}
	if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
		return 0;
	return n;
}

static int hex4(const unsigned char *p, uint32_t *v)
{
	*v = 0;
	for (int i = 0; i < 4; i++) {
		unsigned c = p[i], d;
		if (c >= '0' && c <= '9')
			d = c - '0';
		else if (c >= 'a' && c <= 'f')
			d = c - 'a' + 10;
		else if (c >= 'A' && c <= 'F')
			d = c - 'A' + 10;
		else
			return -1;
		*v = *v << 4 | d;
	}
	return 0;
}

/* A \u escape at s->p (the backslash): no NUL, surrogates only as a pair. */
static int unicode_escape(struct scan *s)
{
	uint32_t cp, lo;
	if (s->end - s->p < 6 || hex4(s->p + 2, &cp) < 0)
		return fail(s, "an invalid \\u escape");
	if (cp == 0)
		return fail(s, "a \\u0000 escape (NUL)");
	if (cp >= 0xdc00 && cp <= 0xdfff)
		return fail(s, "an unpaired surrogate escape");
	s->p += 6;
	if (cp < 0xd800 || cp > 0xdbff)
		return 0;
	if (s->end - s->p < 6 || s->p[0] != '\\' || s->p[1] != 'u' || hex4(s->p + 2, &lo) < 0 ||
	    lo < 0xdc00 || lo > 0xdfff) {
		s->p -= 6;
		return fail(s, "an unpaired surrogate escape");
	}
	s->p += 6;
	return 0;
}

/* A string at s->p ('"'); a key when `key` (escapes refused), its text in *k. */
static int string(struct scan *s, int key, struct key *k)
{
	s->p++;
	if (k)
		k->at = s->p;
	for (;;) {
		if (s->p >= s->end)
			return fail(s, "a string that does not end");
		const unsigned c = *s->p;
		if (c == '"') {
			if (k)
				k->len = (size_t)(s->p - k->at);
			s->p++;
			return 0;
		}
		if (c < 0x20)
			return fail(s, c ? "a control character in a string" : "a NUL byte");
		if (c >= 0x80) {
			const size_t n = json_utf8_len(s->p, s->end);
			if (!n)
				return fail(s, "text that is not UTF-8");
			s->p += n;
			continue;
		}
		if (c != '\\') {
			s->p++;
			continue;
		}
		if (key) {
			/* say so when the escape hides a NUL (a key cut short in C) */
			uint32_t cp = 1;
			if (s->end - s->p >= 6 && s->p[1] == 'u' && hex4(s->p + 2, &cp) < 0)
				cp = 1;
			return fail(s, cp ? "an escape inside a key"
					  : "an escape inside a key (\\u0000, a NUL)");
		}
		if (s->end - s->p < 2)
			return fail(s, "a string that does not end");
		const unsigned e = s->p[1];
		if (e == 'u') {
			if (unicode_escape(s) < 0)
				return -1;
		} else if (e && strchr("\"\\/bfnrt", (int)e)) {
			s->p += 2;
		} else {
			return fail(s, "an invalid escape in a string");
		}
	}
}

static int digits(struct scan *s)
{
	const unsigned char *b = s->p;
	while (s->p < s->end && *s->p >= '0' && *s->p <= '9')
		s->p++;
	return s->p > b ? 0 : fail(s, "a malformed number");
}

/* RFC 8259: -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)? */
static int number(struct scan *s)
{
	if (*s->p == '-')
		s->p++;
	if (s->p < s->end && *s->p == '0')
		s->p++;
	else if (s->p >= s->end || *s->p < '1' || *s->p > '9')
		return fail(s, "a malformed number");
	else if (digits(s) < 0)
		return -1;
	if (s->p < s->end && *s->p == '.') {
		s->p++;
		if (digits(s) < 0)
			return -1;
	}
	if (s->p < s->end && (*s->p == 'e' || *s->p == 'E')) {
		s->p++;
		if (s->p < s->end && (*s->p == '+' || *s->p == '-'))
			s->p++;
		if (digits(s) < 0)
			return -1;
	}
	return 0;
}

static int literal(struct scan *s, const char *word)
{
	const size_t n = strlen(word);
	if ((size_t)(s->end - s->p) < n || memcmp(s->p, word, n))
		return fail(s, "an unexpected character");
	s->p += n;
	return 0;
}

static int value(struct scan *s, int depth);

/* After a member or an element: 1 on ',', 0 on `close`, -1 otherwise. */
static int next(struct scan *s, unsigned char close)
{
	skip_ws(s);
	if (s->p < s->end && *s->p == ',') {
		s->p++;
		return 1;
	}
	if (s->p < s->end && *s->p == close) {
		s->p++;
		return 0;
	}
	return fail(s, close == '}' ? "expected ',' or '}'" : "expected ',' or ']'");
}

/* An object at s->p, at depth `depth` (itself counted): every key once. */
static int object(struct scan *s, int depth)
{
	const size_t base = s->nkeys;
	int r = 1;
	s->p++;
	skip_ws(s);
	if (s->p < s->end && *s->p == '}') {
		s->p++;
		return 0;
	}
	while (r == 1) {
		skip_ws(s);
		if (s->p >= s->end || *s->p != '"')
			return fail(s, "expected a key");
		if (s->nkeys == JSON_STRICT_MAX_KEYS)
			return fail(s, "too many keys");
		const unsigned char *at = s->p;
		struct key *k = &s->keys[s->nkeys];
		if (string(s, 1, k) < 0)
			return -1;
		for (size_t i = base; i < s->nkeys; i++)
			if (s->keys[i].len == k->len && !memcmp(s->keys[i].at, k->at, k->len)) {
				s->p = at;
				return fail(s, "a duplicate key");
			}
		s->nkeys++;
		skip_ws(s);
		if (s->p >= s->end || *s->p != ':')
			return fail(s, "expected ':'");
		s->p++;
		if (value(s, depth) < 0)
			return -1;
		r = next(s, '}');
	}
	s->nkeys = base; /* the object's keys leave the stack with it */
	return r;
}

static int array(struct scan *s, int depth)
{
	int r = 1;
	s->p++;
	skip_ws(s);
	if (s->p < s->end && *s->p == ']') {
		s->p++;
		return 0;
	}
	while (r == 1) {
		if (value(s, depth) < 0)
			return -1;
		r = next(s, ']');
	}
	return r;
}

/* A value at s->p inside `depth` containers. */
static int value(struct scan *s, int depth)
{
	skip_ws(s);
	if (s->p >= s->end)
		return fail(s, "expected a value");
	if ((*s->p == '{' || *s->p == '[') && depth >= s->max_depth)
		return fail(s, "nested too deeply");
	switch (*s->p) {
	case '{': return object(s, depth + 1);
	case '[': return array(s, depth + 1);
	case '"': return string(s, 0, NULL);
	case 't': return literal(s, "true");
	case 'f': return literal(s, "false");
	case 'n': return literal(s, "null");
	case '-': return number(s);
	default:
		if (*s->p >= '0' && *s->p <= '9')
			return number(s);
		if (!*s->p)
			return fail(s, "a NUL byte");
		return fail(s, *s->p >= 0x80 && !json_utf8_len(s->p, s->end) ? "text that is not UTF-8"
									    : "an unexpected character");
	}
}

int json_strict_check(const char *text, size_t len, int max_depth, char *why, size_t why_len)
{
	struct scan s;
	if (!text)
		text = "", len = 0;
	s.p = s.start = (const unsigned char *)text;
	s.end = s.p + len;
	s.max_depth = max_depth;
	s.err = NULL;
	s.err_at = 0;
	s.nkeys = 0;
	int r = value(&s, 0);
	if (r == 0) {
		skip_ws(&s);
		if (s.p < s.end)
			r = fail(&s, *s.p ? "text after the value" : "a NUL byte after the value");
	}
	if (r == 0)
		return 0;
	if (why && why_len)
		snprintf(why, why_len, "%s at byte %zu", s.err, s.err_at);
	return -EINVAL;
}
