/* SPDX-License-Identifier: MIT */
/*
 * The one strict JSON check of what clients send the plugins' servers (the
 * http sink's POST bodies, the foxglove sink's text messages), before json-c
 * parses them.  RFC 8259 and more:
 *  - valid UTF-8 throughout (no overlong forms, no UTF-16 surrogates, nothing
 *    past U+10FFFF), no NUL byte and no \u0000 escape anywhere, no unpaired
 *    surrogate escape;
 *  - numbers and literals exactly as the RFC's grammar has them;
 *  - one value and nothing after it but whitespace; nesting at most max_depth;
 *  - no key twice in one object, and no escape at all inside a key.
 * Why keys may not hold escapes: json-c cuts a key at an escaped NUL, and
 * "radius" and "r\u0061dius" are one key spelled two ways; a check comparing
 * keys as written would let such a pair through as two keys while the parser
 * sees one.  No client of ours needs an escape in a key, so refusing them makes
 * the keys compared here the keys json-c keeps, byte for byte.
 * Text that passes means the same to every conforming parser: json-c cannot be
 * told one thing while the check sees another.
 */
#ifndef DAO_PLUGIN_JSON_STRICT_H
#define DAO_PLUGIN_JSON_STRICT_H

#include <stddef.h>

/* keys held at once by the objects being read (all levels); more is refused */
#define JSON_STRICT_MAX_KEYS 512

/*
 * 0 if `text` (len bytes, not NUL-terminated) is strict JSON nested at most
 * max_depth deep (a scalar at the top is depth 0, each object or array one
 * more); else -EINVAL with the reason and its byte offset in why ("... at byte
 * N": plain ASCII, never a copy of the input).  Allocates nothing.
 */
int json_strict_check(const char *text, size_t len, int max_depth, char *why, size_t why_len);

/* The length (1..4) of the UTF-8 sequence at p (p < end; RFC 3629: no overlong
   forms, no surrogates, at most U+10FFFF), or 0 if it is not one. */
size_t json_utf8_len(const unsigned char *p, const unsigned char *end);

#endif
