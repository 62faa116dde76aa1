/* SPDX-License-Identifier: MIT */
/* Part of libdepthao-io (pkg-config depthao-io, <depthao/io.h>), not of the AO core libdepthao. */
/*
 * The URIs of sources and sinks:
 *     [NAME:]REST[?KEY=VALUE&KEY=VALUE...]
 * NAME picks the plugin (dao_uri_prefix_len()); REST is its path, device or
 * address; the options follow a '?'.  Every plugin, built-in or a module,
 * reads its options with dao_options_*(), so all of them follow one syntax
 * and fail the same way, naming the plugin, the key and the value:
 *     rtsp: unknown option 'fsp' (known: quality, transport)
 *     http: 'quality' must be an integer in 1..100, got 'x'
 *
 * Syntax: options are separated by '&'; empty ones ("a=1&&b=2", a trailing
 * '&') are skipped.  Each is KEY=VALUE with a non-empty key and value (the
 * value is everything after the first '='; it may hold '=' and '?').  No
 * percent-decoding: the bytes are taken as they are.  A key given twice, a
 * key not in the plugin's list, or an option without '=' is an error.
 */
#ifndef DEPTHAO_URI_H
#define DEPTHAO_URI_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/api.h>
#include <depthao/error.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Length of a plugin prefix "name:" at the start of a URI: two or more of
 * [a-z0-9_-] then ':' (so "C:\x", "./a:b" or "/x:y" are not prefixes); 0 if
 * none.  How dao_source_open() and dao_sink_open() split a URI.
 */
static inline size_t dao_uri_prefix_len(const char *uri)
{
	size_t i = 0;
	while ((uri[i] >= 'a' && uri[i] <= 'z') || (uri[i] >= '0' && uri[i] <= '9') ||
	       uri[i] == '-' || uri[i] == '_')
		i++;
	return i > 1 && uri[i] == ':' ? i : 0;
}

/*
 * Length of the part of `uri` before its options: the index of the '?' that
 * starts them, or strlen(uri) when there are none.  They start at the last
 * '?' followed by one of the `known` keys (NULL-terminated; may be NULL)
 * and '=', so a '?' in a file name stays in the name; failing that, at the
 * last '?' if a '=' follows it, so that a misspelt key is reported by
 * dao_options_parse() rather than taken for part of a name.
 */
DAO_API size_t dao_uri_path_len(const char *uri, const char *const *known);

/* A parsed option string; read it with the getters below. */
struct dao_options;

/*
 * Parses `text` (the part after the '?', without it; NULL or "" is no
 * options).  `who` names the plugin in messages ("rtsp", "v4l2 output");
 * `known` lists the keys it takes (NULL-terminated).  0 and *out (free with
 * dao_options_free()), or -EINVAL with a message naming the option: an
 * unknown key (with the list of known ones), a key given twice, an option
 * without '=', with an empty key or an empty value; -ENOMEM.
 */
DAO_API int dao_options_parse(struct dao_options **out, const char *who, const char *text,
			      const char *const *known, struct dao_error *err);
/* Frees what dao_options_parse() made (NULL is allowed). */
DAO_API void dao_options_free(struct dao_options *opts);

/*
 * The getters: 1 when the option is given and *value is set, 0 when it is
 * not given (*value is left as it is: set the default before), or -EINVAL
 * with a message naming the key, what it must be and the value given.
 */

/* The raw value of `key`, NULL if it is not given; valid until dao_options_free(). */
DAO_API const char *dao_options_value(const struct dao_options *opts, const char *key);

/* A copy of the value into buf[cap]; -EINVAL if it does not fit (cap - 1 bytes at most). */
DAO_API int dao_options_get_string(const struct dao_options *opts, const char *key, char *buf,
				   size_t cap, struct dao_error *err);

/* A decimal integer (an optional '-', digits) in min..max. */
DAO_API int dao_options_get_int(const struct dao_options *opts, const char *key, int64_t min,
				int64_t max, int64_t *value, struct dao_error *err);

/* Flags of dao_options_get_double(): the bound itself is outside the range. */
/* dao_options_get_double(): the minimum itself is outside the range. */
#define DAO_OPTIONS_MIN_EXCLUSIVE 1u
/* dao_options_get_double(): the maximum itself is outside the range. */
#define DAO_OPTIONS_MAX_EXCLUSIVE 2u

/* A finite number (strtod's syntax, no inf or nan) in [min, max] (see the flags). */
DAO_API int dao_options_get_double(const struct dao_options *opts, const char *key, double min,
				   double max, unsigned flags, double *value,
				   struct dao_error *err);

/* true or 1 -> 1, false or 0 -> 0. */
DAO_API int dao_options_get_bool(const struct dao_options *opts, const char *key, int *value,
				 struct dao_error *err);

/* One of `names` (NULL-terminated), compared ignoring ASCII case; *index its position. */
DAO_API int dao_options_get_enum(const struct dao_options *opts, const char *key,
				 const char *const *names, int *index, struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
