/* SPDX-License-Identifier: MIT */
/*
 * The parameter table (param_rows.h): one row per field of struct
 * dao_params.  Parsing, range checks, printing, help text and the defaults
 * are all driven from it.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/params.h>

#include "core/error_internal.h"
#include "params/params_abi.h"
#include "params/presets.h"
#include "simd/cpu_internal.h"

#define OFF(field) offsetof(struct dao_params, field)

static const char *const algorithm_names[] = { "gtao", "hbao", "ssao", "edl", "vbao", "none", NULL };
static const char *const vbao_thickness_names[] = { "constant", "image", NULL };
static const char *const prefilter_names[] = { "none", "bilateral", "domain", NULL };
static const char *const noise_model_names[] = { "fixed", "auto", "auto-prefilter", NULL };
static const char *const depth_motion_names[] = { "off", "icp", "source", "source+icp", NULL };
static const char *const normals_names[] = { "smaller-delta", "wide", NULL };
static const char *const noise_names[] = { "ign", "r2", "none", "tile", NULL };
static const char *const denoise_names[] = { "none", "plane", "bilateral", NULL };
static const char *const shade_names[] = { "lambert", "turbo", "jet", "gray", "ao", NULL };

#define RT DAO_PARAM_RUNTIME
#define SH (DAO_PARAM_RUNTIME | DAO_PARAM_SHADING)

/* The public table: every column of param_rows.h but the default. */
#define ROW(name, help, unit, type, field, min, max, names, flags, def) \
	{ name, help, unit, DAO_PARAM_##type, OFF(field), min, max, names, flags },
static const struct dao_param_info table[] = {
#include "params/param_rows.h"
};
#undef ROW

/* The defaults: the last column of param_rows.h. */
#define ROW(name, help, unit, type, field, min, max, names, flags, def) .field = def,
const struct dao_params dao_param_defaults = {
	.size = sizeof(struct dao_params),
#include "params/param_rows.h"
};
#undef ROW

size_t dao_params_size(void)
{
	return sizeof(struct dao_params);
}

const struct dao_param_info *dao_param_table(size_t *count)
{
	if (count)
		*count = sizeof table / sizeof table[0];
	return table;
}

/* Names compare with '-' and '_' as the same character. */
static int name_eq(const char *a, const char *b)
{
	for (; *a && *b; a++, b++) {
		char ca = *a == '_' ? '-' : *a, cb = *b == '_' ? '-' : *b;
		if (ca != cb)
			return 0;
	}
	return *a == *b;
}

const struct dao_param_info *dao_param_find(const char *name)
{
	if (!name)
		return NULL;
	for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
		if (name_eq(table[i].name, name))
			return &table[i];
	return NULL;
}

static const char *const quality_names[DAO_QUALITY_COUNT] = { "low", "medium", "high", "ultra" };

const char *dao_quality_name(enum dao_quality q)
{
	return (unsigned)q < DAO_QUALITY_COUNT ? quality_names[q] : NULL;
}

int dao_quality_parse(const char *name, enum dao_quality *q, struct dao_error *err)
{
	if (name && strcmp(name, "default") == 0) {
		*q = DAO_QUALITY_DEFAULT;
		return 0;
	}
	for (int i = 0; name && i < DAO_QUALITY_COUNT; i++)
		if (strcmp(name, quality_names[i]) == 0) {
			*q = (enum dao_quality)i;
			return 0;
		}
	return dao_error_set(err, -EINVAL,
			     "unknown quality '%s': use low, medium, high, ultra or default",
			     name ? name : "(null)");
}

static void *field(struct dao_params *p, const struct dao_param_info *pi)
{
	return (char *)p + pi->offset;
}

static const void *cfield(const struct dao_params *p, const struct dao_param_info *pi)
{
	return (const char *)p + pi->offset;
}

/* The caller's struct has a valid size and holds the field of `pi`. */
static int in_struct(const struct dao_params *p, const struct dao_param_info *pi,
		     struct dao_error *err)
{
	int r = dao_params_check_size(p, err);
	if (r < 0)
		return r;
	if (!dao_params_has(p, pi->offset, 4)) /* every field is a 4-byte int, float or uint32_t */
		return dao_error_set(err, -ENOENT,
				     "parameter '%s' is newer than the program's struct dao_params "
				     "(%u bytes); rebuild the program against this depthao",
				     pi->name, (unsigned)p->size);
	return 0;
}

static void format_enum_list(const struct dao_param_info *pi, char *buf, size_t len)
{
	size_t used = 0;
	buf[0] = '\0';
	for (int i = 0; pi->enum_names[i] && used < len; i++)
		used += (size_t)snprintf(buf + used, len - used, "%s%s", i ? ", " : "",
					 pi->enum_names[i]);
}

static int parse_color(const char *s, uint32_t *out)
{
	if (*s == '#')
		s++;
	if (strlen(s) != 6)
		return -1;
	char *end;
	unsigned long v = strtoul(s, &end, 16);
	if (*end)
		return -1;
	*out = (uint32_t)v;
	return 0;
}

int dao_params_set(struct dao_params *p, const char *name, const char *value,
		   struct dao_error *err)
{
	const struct dao_param_info *pi = dao_param_find(name);
	if (!pi)
		return dao_error_set(err, -EINVAL, "unknown parameter '%s'", name ? name : "(null)");
	int r = in_struct(p, pi, err);
	if (r < 0)
		return r;
	if (!value || !*value)
		return dao_error_set(err, -EINVAL, "parameter '%s' needs a value", pi->name);
	char *end;
	switch (pi->type) {
	case DAO_PARAM_FLOAT: {
		double v = strtod(value, &end);
		if (*end || !isfinite(v))
			return dao_error_set(err, -EINVAL, "%s: '%s' is not a number", pi->name,
					     value);
		if (v < pi->min || v > pi->max)
			return dao_error_set(err, -EINVAL, "%s: %s is out of range [%g, %g]%s%s",
					     pi->name, value, pi->min, pi->max,
					     pi->unit ? " " : "", pi->unit ? pi->unit : "");
		*(float *)field(p, pi) = (float)v;
		return 0;
	}
	case DAO_PARAM_INT: {
		long v = strtol(value, &end, 10);
		if (*end)
			return dao_error_set(err, -EINVAL, "%s: '%s' is not an integer", pi->name,
					     value);
		if (v < pi->min || v > pi->max)
			return dao_error_set(err, -EINVAL, "%s: %s is out of range [%g, %g]",
					     pi->name, value, pi->min, pi->max);
		*(int *)field(p, pi) = (int)v;
		return 0;
	}
	case DAO_PARAM_ENUM:
		for (int i = 0; pi->enum_names[i]; i++)
			if (strcmp(pi->enum_names[i], value) == 0) {
				*(int *)field(p, pi) = i;
				return 0;
			}
		{
			char list[160];
			format_enum_list(pi, list, sizeof list);
			return dao_error_set(err, -EINVAL, "%s: '%s' is not one of: %s", pi->name,
					     value, list);
		}
	case DAO_PARAM_COLOR: {
		uint32_t c;
		if (parse_color(value, &c))
			return dao_error_set(err, -EINVAL,
					     "%s: '%s' is not a colour; write RRGGBB in hex, e.g. 202040",
					     pi->name, value);
		*(uint32_t *)field(p, pi) = c;
		return 0;
	}
	}
	return dao_error_set(err, -EINVAL, "%s: unsupported parameter type", pi->name);
}

int dao_params_get(const struct dao_params *p, const char *name, char *buf, size_t len,
		   struct dao_error *err)
{
	const struct dao_param_info *pi = dao_param_find(name);
	if (!pi)
		return dao_error_set(err, -EINVAL, "unknown parameter '%s'", name ? name : "(null)");
	int r = in_struct(p, pi, err);
	if (r < 0)
		return r;
	if (!buf || !len)
		return dao_error_set(err, -EINVAL, "%s: no buffer for the value", pi->name);
	int n = 0;
	switch (pi->type) {
	case DAO_PARAM_FLOAT:
		n = snprintf(buf, len, "%g", (double)*(const float *)cfield(p, pi));
		break;
	case DAO_PARAM_INT:
		n = snprintf(buf, len, "%d", *(const int *)cfield(p, pi));
		break;
	case DAO_PARAM_ENUM: {
		int v = *(const int *)cfield(p, pi);
		int count = 0;
		while (pi->enum_names[count])
			count++;
		n = snprintf(buf, len, "%s", v >= 0 && v < count ? pi->enum_names[v] : "invalid");
		break;
	}
	case DAO_PARAM_COLOR:
		n = snprintf(buf, len, "%06x", (unsigned)*(const uint32_t *)cfield(p, pi));
		break;
	}
	if (n < 0 || (size_t)n >= len)
		return dao_error_set(err, -EOVERFLOW, "%s: buffer of %zu bytes is too small",
				     pi->name, len);
	return 0;
}

int dao_params_validate(const struct dao_params *caller, struct dao_error *err)
{
	struct dao_params full;
	int r = dao_params_import(&full, caller, err);
	if (r < 0)
		return r;
	const struct dao_params *p = &full;
	for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
		const struct dao_param_info *pi = &table[i];
		switch (pi->type) {
		case DAO_PARAM_FLOAT: {
			float v = *(const float *)cfield(p, pi);
			if (!isfinite(v) || v < pi->min || v > pi->max)
				return dao_error_set(err, -EINVAL, "%s: %g is out of range [%g, %g]",
						     pi->name, (double)v, pi->min, pi->max);
			break;
		}
		case DAO_PARAM_INT: {
			int v = *(const int *)cfield(p, pi);
			if (v < pi->min || v > pi->max)
				return dao_error_set(err, -EINVAL, "%s: %d is out of range [%g, %g]",
						     pi->name, v, pi->min, pi->max);
			break;
		}
		case DAO_PARAM_ENUM: {
			int v = *(const int *)cfield(p, pi), count = 0;
			while (pi->enum_names[count])
				count++;
			if (v < 0 || v >= count) {
				char list[160];
				format_enum_list(pi, list, sizeof list);
				return dao_error_set(err, -EINVAL, "%s: value %d is not one of: %s",
						     pi->name, v, list);
			}
			break;
		}
		case DAO_PARAM_COLOR:
			if (*(const uint32_t *)cfield(p, pi) > 0xffffff)
				return dao_error_set(err, -EINVAL, "%s: 0x%x is not an RRGGBB colour",
						     pi->name, (unsigned)*(const uint32_t *)cfield(p, pi));
			break;
		}
	}
	if (p->depth_min >= p->depth_max)
		return dao_error_set(err, -EINVAL, "depth-min %g must be less than depth-max %g",
				     (double)p->depth_min, (double)p->depth_max);
	if (p->near_m && p->far_m && p->near_m >= p->far_m)
		return dao_error_set(err, -EINVAL, "near %g must be less than far %g (or 0 for auto)",
				     (double)p->near_m, (double)p->far_m);
	if (p->min_screen_radius > p->max_screen_radius)
		return dao_error_set(err, -EINVAL,
				     "min-screen-radius %g must not exceed max-screen-radius %g",
				     (double)p->min_screen_radius, (double)p->max_screen_radius);
	if (p->ssao_min >= p->ssao_max)
		return dao_error_set(err, -EINVAL, "ssao-min %g must be less than ssao-max %g",
				     (double)p->ssao_min, (double)p->ssao_max);
	return 0;
}
