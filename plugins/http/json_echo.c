/* SPDX-License-Identifier: MIT */
/*
 * Text made safe to echo inside a JSON reply: an error message may quote what a
 * client sent (a path, a key), which may be any bytes; a strict JSON client must
 * still parse the reply.  (What a client POSTs is checked by json_strict_check,
 * plugins/common/json_strict.h.)
 */
#include <stdio.h>
#include <string.h>

#include "http_sink.h"
#include "json_strict.h"

size_t http_json_safe(char *dst, size_t cap, const char *src)
{
	const unsigned char *p = (const unsigned char *)src, *end = p + strlen(src);
	size_t o = 0;
	if (!cap)
		return 0;
	while (p < end) {
		size_t n = json_utf8_len(p, end);
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
