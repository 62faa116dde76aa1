/* SPDX-License-Identifier: MIT */
/*
 * What json-c lets through and the viewer must not: a strict check of a POST
 * body before it is parsed, and text made safe to echo inside a JSON reply.
 * json-c keeps "\u0000" in a string but cuts an object key at it, takes the
 * last of two equal keys and passes bytes that are not UTF-8 through; here
 * each of those is an error naming where it is.
 */
#include <stdio.h>
#include <string.h>

#include "http_sink.h"

#define MAX_DEPTH 32

struct scan {
	const unsigned char *p, *end, *start;
	char *msg;
	size_t cap;
};

static int fail_at(struct scan *s, const char *what)
{
	snprintf(s->msg, s->cap, "%s at byte %zu", what, (size_t)(s->p - s->start));
	return -1;
}

/* Length of the UTF-8 sequence at p (RFC 3629: no overlongs, no surrogates, <= U+10FFFF), 0 if invalid. */
static size_t utf8_len(const unsigned char *p, const unsigned char *end)
{
	const unsigned c = p[0];
	if (c < 0x80)
		return 1;
	size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
	if (!n || (size_t)(end - p) < n)
		return 0;
	for (size_t i = 1; i < n; i++)
		if ((p[i] & 0xC0) != 0x80)
			return 0;
	if ((c == 0xE0 && p[1] < 0xA0) || (c == 0xED && p[1] > 0x9F) || (c == 0xF0 && p[1] < 0x90) ||
	    (c == 0xF4 && p[1] > 0x8F))
		return 0;
	return n;
}

static void skip_ws(struct scan *s)
{
	while (s->p < s->end && (*s->p == ' ' || *s->p == '\t' || *s->p == '\n' || *s->p == '\r'))
		s->p++;
}

static int hex4(const unsigned char *p, unsigned *v)
{
	*v = 0;
	for (int i = 0; i < 4; i++) {
		unsigned c = p[i], d;
		if (c >= '0' && c <= '9')
			d = c - '0';
		else if ((c | 0x20) >= 'a' && (c | 0x20) <= 'f')
			d = (c | 0x20) - 'a' + 10;
		else
			return -1;
		*v = *v << 4 | d;
	}
	return 0;
}

/* A string at s->p (the opening quote); its raw text (between the quotes) in *text, *len. */
static int scan_string(struct scan *s, const unsigned char **text, size_t *len)
{
	s->p++;
	*text = s->p;
	while (s->p < s->end && *s->p != '"') {
		if (*s->p < 0x20)
			return fail_at(s, "a control character inside a string");
		if (*s->p == '\\') {
			if (s->end - s->p < 2)
				break;
			const unsigned char e = s->p[1];
			if (e == 'u') {
				unsigned v;
				if (s->end - s->p < 6 || hex4(s->p + 2, &v) < 0)
					return fail_at(s, "a bad \\u escape");
				if (v == 0)
					return fail_at(s, "NUL (\\u0000) inside a string");
				if (v >= 0xD800 && v <= 0xDBFF) { /* a high surrogate needs its low one */
					unsigned lo;
					if (s->end - s->p < 12 || s->p[6] != '\\' || s->p[7] != 'u' ||
					    hex4(s->p + 8, &lo) < 0 || lo < 0xDC00 || lo > 0xDFFF)
						return fail_at(s, "a lone surrogate in a \\u escape");
					s->p += 6;
				} else if (v >= 0xDC00 && v <= 0xDFFF) {
					return fail_at(s, "a lone surrogate in a \\u escape");
				}
				s->p += 6;
				continue;
			}
			if (!strchr("\"\\/bfnrt", e) || !e)
				return fail_at(s, "a bad escape");
			s->p += 2;
			continue;
		}
		const size_t n = utf8_len(s->p, s->end);
		if (!n)
			return fail_at(s, "text that is not UTF-8");
		s->p += n;
	}
	if (s->p >= s->end)
		return fail_at(s, "an unterminated string");
	*len = (size_t)(s->p - *text);
	s->p++;
	return 0;
}

static int scan_value(struct scan *s, int depth);

/* An object at s->p: every key once (compared as written: "a" and "\u0061" are two
   spellings that json-c would merge, so an escape in a key is refused outright). */
static int scan_object(struct scan *s, int depth)
{
	const unsigned char *keys[256];
	size_t klen[256], nkeys = 0;
	s->p++;
	skip_ws(s);
	if (s->p < s->end && *s->p == '}') {
		s->p++;
		return 0;
	}
	for (;;) {
		skip_ws(s);
		if (s->p >= s->end || *s->p != '"')
			return fail_at(s, "expected a key");
		const unsigned char *k;
		size_t kl;
		const unsigned char *at = s->p;
		if (scan_string(s, &k, &kl) < 0)
			return -1;
		if (memchr(k, '\\', kl)) {
			s->p = at;
			return fail_at(s, "an escape inside a key");
		}
		for (size_t i = 0; i < nkeys; i++)
			if (klen[i] == kl && !memcmp(keys[i], k, kl)) {
				snprintf(s->msg, s->cap, "the key \"%.*s\" appears twice (at byte %zu)",
					 (int)(kl > 64 ? 64 : kl), (const char *)k, (size_t)(at - s->start));
				return -1;
			}
		if (nkeys == sizeof keys / sizeof keys[0])
			return fail_at(s, "too many keys in one object");
		keys[nkeys] = k;
		klen[nkeys++] = kl;
		skip_ws(s);
		if (s->p >= s->end || *s->p != ':')
			return fail_at(s, "expected ':'");
		s->p++;
		if (scan_value(s, depth + 1) < 0)
			return -1;
		skip_ws(s);
		if (s->p < s->end && *s->p == ',') {
			s->p++;
			continue;
		}
		if (s->p < s->end && *s->p == '}') {
			s->p++;
			return 0;
		}
		return fail_at(s, "expected ',' or '}'");
	}
}

static int scan_value(struct scan *s, int depth)
{
	if (depth > MAX_DEPTH)
		return fail_at(s, "nested too deep");
	skip_ws(s);
	if (s->p >= s->end)
		return fail_at(s, "expected a value");
	const unsigned char c = *s->p;
	if (c == '{')
		return scan_object(s, depth);
	if (c == '"') {
		const unsigned char *t;
		size_t l;
		return scan_string(s, &t, &l);
	}
	if (c == '[') {
		s->p++;
		skip_ws(s);
		if (s->p < s->end && *s->p == ']') {
			s->p++;
			return 0;
		}
		for (;;) {
			if (scan_value(s, depth + 1) < 0)
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
			return fail_at(s, "expected ',' or ']'");
		}
	}
	/* numbers and literals: their grammar is json-c's to check; here only their bytes */
	const unsigned char *from = s->p;
	while (s->p < s->end && strchr("0123456789+-.eEtruefalsn", *s->p) && *s->p)
		s->p++;
	if (s->p == from)
		return fail_at(s, *s->p >= 0x80 && !utf8_len(s->p, s->end) ? "text that is not UTF-8"
									   : "an unexpected character");
	return 0;
}

int http_json_check(const char *body, size_t len, char *msg, size_t cap)
{
	struct scan s = {(const unsigned char *)body, (const unsigned char *)body + len,
			 (const unsigned char *)body, msg, cap};
	if (memchr(body, '\0', len)) {
		s.p = memchr(s.p, '\0', len);
		return fail_at(&s, "a NUL byte");
	}
	if (scan_value(&s, 0) < 0)
		return -1;
	skip_ws(&s);
	if (s.p != s.end)
		return fail_at(&s, "text after the JSON value");
	return 0;
}

size_t http_json_safe(char *dst, size_t cap, const char *src)
{
	const unsigned char *p = (const unsigned char *)src, *end = p + strlen(src);
	size_t o = 0;
	if (!cap)
		return 0;
	while (p < end) {
		size_t n = utf8_len(p, end);
		char esc[8];
		const char *out = (const char *)p;
		size_t outlen = n;
		if (!n) { /* a byte that is not UTF-8: shown as \xHH, in plain ASCII */
			snprintf(esc, sizeof esc, "\\x%02X", *p);
			out = esc;
			outlen = 4;
			n = 1;
		}
		if (o + outlen >= cap)
			break; /* whole characters only */
		memcpy(dst + o, out, outlen);
		o += outlen;
		p += n;
	}
	dst[o] = '\0';
	return o;
}
