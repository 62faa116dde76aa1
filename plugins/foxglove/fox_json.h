/* SPDX-License-Identifier: MIT */
/*
 * Strict JSON for what clients send the foxglove sink (RFC 8259 and more):
 * valid UTF-8 throughout (no overlong forms, no surrogates), no NUL byte and
 * no \u0000 escape anywhere, no unpaired surrogate escape, no duplicate key
 * in an object (compared after unescaping), one value and nothing after it
 * but whitespace, nesting at most FOX_JSON_MAX_DEPTH.  A parser that keeps
 * the first or the last of two keys, or cuts a string at a NUL, cannot be
 * told one thing while the check sees another: text that passes this check
 * means the same to every conforming parser.
 */
#ifndef DAO_FOX_JSON_H
#define DAO_FOX_JSON_H

#include <stddef.h>

#define FOX_JSON_MAX_DEPTH 16
#define FOX_JSON_MAX_KEYS 256 /* keys in one object */

/*
 * 0 if `text` (len bytes, not NUL-terminated) is strict JSON; else -EINVAL with
 * the reason and byte offset in why (plain ASCII, never a copy of the input).
 */
int fox_json_check(const char *text, size_t len, char *why, size_t why_len);

#endif
