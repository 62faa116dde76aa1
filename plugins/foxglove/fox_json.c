/* SPDX-License-Identifier: MIT */
/* The strict JSON check of fox_json.h: a recursive-descent recogniser. */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fox_json.h"

struct scan {
	const unsigned char *p, *end, *start;
	const char *err;
	size_t err_at;
	/* the decoded keys of the objects being read, one stack of spans */
	unsigned char *keys;
	size_t keys_len, keys_cap;
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

/* One UTF-8 sequence at s->p (its first byte >= 0x80): its length, or -1. */
static int utf8_len(const unsigned char *p, const unsigned char *end)
{
	unsigned c = p[0];
	int n;
	uint32_t cp, min;
	if (c >= 0xc2 && c <= 0xdf) {
		n = 2, cp = c & 0x1f, min = 0x80;
	} else if (c >= 0xe0 && c <= 0xef) {
		n = 3, cp = c & 0x0f, min = 0x800;
	} else if (c >= 0xf0 && c <= 0xf4) {
		n = 4, cp = c & 0x07, min = 0x10000;
	} else {
		return -1; /* a continuation byte, an overlong lead (c0, c1) or past U+10FFFF */
	}
	if (end - p < n)
		return -1;
	for (int i = 1; i < n; i++) {
		if ((p[i] & 0xc0) != 0x80)
			return -1;
		cp = cp << 6 | (p[i] & 0x3f);
	}
	if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
		return -1;
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

/* Appends the code point's UTF-8 to the key buffer (when decoding a key). */
static int put_key(struct scan *s, const unsigned char *b, size_t n)
{
	if (s->keys_len + n > s->keys_cap) {
		size_t cap = s->keys_cap ? s->keys_cap * 2 : 256;
		while (cap < s->keys_len + n)
			cap *= 2;
		unsigned char *k = realloc(s->keys, cap);
		if (!k)
			return fail(s, "out of memory");
		s->keys = k;
		s->keys_cap = cap;
	}
	memcpy(s->keys + s->keys_len, b, n);
	s->keys_len += n;
	return 0;
}

static int put_cp(struct scan *s, uint32_t cp)
{
	unsigned char b[4];
	size_t n;
	if (cp < 0x80) {
		b[0] = (unsigned char)cp, n = 1;
	} else if (cp < 0x800) {
		b[0] = (unsigned char)(0xc0 | cp >> 6), b[1] = (unsigned char)(0x80 | (cp & 0x3f)), n = 2;
	} else if (cp < 0x10000) {
		b[0] = (unsigned char)(0xe0 | cp >> 12), b[1] = (unsigned char)(0x80 | (cp >> 6 & 0x3f));
		b[2] = (unsigned char)(0x80 | (cp & 0x3f)), n = 3;
	} else {
		b[0] = (unsigned char)(0xf0 | cp >> 18), b[1] = (unsigned char)(0x80 | (cp >> 12 & 0x3f));
		b[2] = (unsigned char)(0x80 | (cp >> 6 & 0x3f)), b[3] = (unsigned char)(0x80 | (cp & 0x3f));
		n = 4;
	}
	return put_key(s, b, n);
}

/* A string at s->p ('"'); decoded onto the key buffer when `key`. */
static int string(struct scan *s, int key)
{
	s->p++;
	for (;;) {
		if (s->p >= s->end)
			return fail(s, "a string does not end");
		unsigned c = *s->p;
		if (c == '"') {
			s->p++;
			return 0;
		}
		if (c < 0x20)
			return fail(s, c ? "a control character in a string" : "a NUL byte");
		if (c >= 0x80) {
			int n = utf8_len(s->p, s->end);
			if (n < 0)
				return fail(s, "invalid UTF-8");
			if (key && put_key(s, s->p, (size_t)n) < 0)
				return -1;
			s->p += n;
			continue;
		}
		if (c != '\\') {
			if (key && put_key(s, s->p, 1) < 0)
				return -1;
			s->p++;
			continue;
		}
		if (s->end - s->p < 2)
			return fail(s, "a string does not end");
		unsigned e = s->p[1];
		static const char plain[] = "\"\\/bfnrt";
		static const char value[] = "\"\\/\b\f\n\r\t";
		const char *at = e ? strchr(plain, (int)e) : NULL;
		if (at) {
			if (key && put_cp(s, (uint32_t)(unsigned char)value[at - plain]) < 0)
				return -1;
			s->p += 2;
			continue;
		}
		if (e != 'u')
			return fail(s, "an invalid escape in a string");
		uint32_t cp;
		if (s->end - s->p < 6 || hex4(s->p + 2, &cp) < 0)
			return fail(s, "an invalid \\u escape");
		if (cp == 0)
			return fail(s, "a \\u0000 escape (NUL)");
		s->p += 6;
		if (cp >= 0xdc00 && cp <= 0xdfff)
			return fail(s, "an unpaired surrogate escape");
		if (cp >= 0xd800 && cp <= 0xdbff) {
			uint32_t lo;
			if (s->end - s->p < 6 || s->p[0] != '\\' || s->p[1] != 'u' ||
			    hex4(s->p + 2, &lo) < 0 || lo < 0xdc00 || lo > 0xdfff)
				return fail(s, "an unpaired surrogate escape");
			cp = 0x10000 + ((cp - 0xd800) << 10) + (lo - 0xdc00);
			s->p += 6;
		}
		if (key && put_cp(s, cp) < 0)
			return -1;
	}
}

static int digits(struct scan *s)
{
	const unsigned char *b = s->p;
	while (s->p < s->end && *s->p >= '0' && *s->p <= '9')
		s->p++;
	return s->p > b ? 0 : fail(s, "a malformed number");
}

static int number(struct scan *s)
{
	if (*s->p == '-')
		s->p++;
	if (s->p < s->end && *s->p == '0')
		s->p++;
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
	size_t n = strlen(word);
	if ((size_t)(s->end - s->p) < n || memcmp(s->p, word, n))
		return fail(s, "an unexpected character");
	s->p += n;
	return 0;
}

static int value(struct scan *s, int depth);

static int object(struct scan *s, int depth)
{
	/* the keys of this object: spans on the key stack from `base` */
	size_t base = s->keys_len, spans[FOX_JSON_MAX_KEYS + 1];
	unsigned nkeys = 0;
	s->p++;
	skip_ws(s);
	if (s->p < s->end && *s->p == '}') {
		s->p++;
		return 0;
	}
	for (;;) {
		skip_ws(s);
		if (s->p >= s->end || *s->p != '"')
			return fail(s, "expected a key");
		if (nkeys == FOX_JSON_MAX_KEYS)
			return fail(s, "too many keys in an object");
		const size_t start = s->keys_len;
		spans[nkeys] = start;
		if (string(s, 1) < 0)
			return -1;
		const size_t klen = s->keys_len - start;
		for (unsigned i = 0; i < nkeys; i++) {
			size_t ilen = spans[i + 1] - spans[i];
			if (ilen == klen && !memcmp(s->keys + spans[i], s->keys + start, klen))
				return fail(s, "a duplicate key");
		}
		spans[++nkeys] = s->keys_len;
		skip_ws(s);
		if (s->p >= s->end || *s->p != ':')
			return fail(s, "expected ':'");
		s->p++;
		if (value(s, depth + 1) < 0)
			return -1;
		skip_ws(s);
		if (s->p < s->end && *s->p == ',') {
			s->p++;
			continue;
		}
		if (s->p < s->end && *s->p == '}') {
			s->p++;
			s->keys_len = base; /* the object's keys leave the stack with it */
			return 0;
		}
		return fail(s, "expected ',' or '}'");
	}
}

static int array(struct scan *s, int depth)
{
	s->p++;
	skip_ws(s);
	if (s->p < s->end && *s->p == ']') {
		s->p++;
		return 0;
	}
	for (;;) {
		if (value(s, depth + 1) < 0)
			return -1;
		skip_ws(s);
		if (s->p < s->end && *s->p == ',') {
			s->p++;
			continue;
		}
		if (s->p < s->end && *s->p == ']') {
			s->p++;
			return 0;
		}
		return fail(s, "expected ',' or ']'");
	}
}

static int value(struct scan *s, int depth)
{
	if (depth > FOX_JSON_MAX_DEPTH)
		return fail(s, "nested too deeply");
	skip_ws(s);
	if (s->p >= s->end)
		return fail(s, "expected a value");
	switch (*s->p) {
	case '{': return object(s, depth);
	case '[': return array(s, depth);
	case '"': return string(s, 0);
	case 't': return literal(s, "true");
	case 'f': return literal(s, "false");
	case 'n': return literal(s, "null");
	default:
		if (*s->p == '-' || (*s->p >= '0' && *s->p <= '9'))
			return number(s);
		return fail(s, *s->p ? "an unexpected character" : "a NUL byte");
	}
}

int fox_json_check(const char *text, size_t len, char *why, size_t why_len)
{
	struct scan s = {.p = (const unsigned char *)text, .end = (const unsigned char *)text + len,
			 .start = (const unsigned char *)text};
	int r = value(&s, 0);
	if (r == 0) {
		skip_ws(&s);
		if (s.p < s.end)
			r = fail(&s, *s.p ? "text after the value" : "a NUL byte after the value");
	}
	free(s.keys);
	if (r == 0)
		return 0;
	if (why && why_len)
		snprintf(why, why_len, "not strict JSON: %s at byte %zu", s.err, s.err_at);
	return -EINVAL;
}
