/* SPDX-License-Identifier: MIT */
/*
 * The parameter table: one row per field of struct dao_params.  Parsing,
 * range checks, printing and help text are all driven from it.
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

static const char *const algorithm_names[] = { "gtao", "hbao", "ssao", "edl", "vbao", NULL };
static const char *const vbao_thickness_names[] = { "constant", "image", NULL };
static const char *const prefilter_names[] = { "none", "bilateral", "domain", NULL };
static const char *const noise_model_names[] = { "fixed", "auto", "auto-prefilter", NULL };
static const char *const normals_names[] = { "smaller-delta", "wide", NULL };
static const char *const noise_names[] = { "ign", "r2", "none", "tile", NULL };
static const char *const denoise_names[] = { "none", "plane", "bilateral", NULL };
static const char *const shade_names[] = { "lambert", "turbo", "jet", "gray", "ao", NULL };

#define RT DAO_PARAM_RUNTIME
#define SH (DAO_PARAM_RUNTIME | DAO_PARAM_SHADING)

static const struct dao_param_info table[] = {
	{ "depth-min", "nearest valid depth; nearer pixels count as no data", "m",
	  DAO_PARAM_FLOAT, OFF(depth_min), 0.0, 1000.0, NULL, RT },
	{ "depth-max", "farthest valid depth; farther pixels count as no data", "m",
	  DAO_PARAM_FLOAT, OFF(depth_max), 0.001, 1000.0, NULL, RT },
	{ "prefilter", "depth prefilter before normals and AO", NULL,
	  DAO_PARAM_ENUM, OFF(prefilter), 0, 0, prefilter_names, RT },
	{ "depth-noise", "sensor noise model sigma(z) = k z^2 with noise-model=fixed; k in 1/m (Kinect v1 ~0.0012)", "1/m",
	  DAO_PARAM_FLOAT, OFF(depth_noise), 0.0, 0.1, NULL, RT },
	{ "prefilter-radius", "footprint of the bilateral prefilter", "px",
	  DAO_PARAM_INT, OFF(prefilter_radius), 1, 8, NULL, RT },
	{ "prefilter-scale", "domain prefilter: spatial scale sigma_s with noise-model=fixed (its cost does not depend on it)", "px",
	  DAO_PARAM_FLOAT, OFF(prefilter_scale), 0.5, 64.0, NULL, RT },
	{ "prefilter-range", "domain prefilter: neighbours differing by more than about this many noise sigmas are not averaged", NULL,
	  DAO_PARAM_FLOAT, OFF(prefilter_range), 0.5, 20.0, NULL, RT },
	{ "prefilter-iterations", "domain prefilter: iterations of a vertical and a horizontal pass", NULL,
	  DAO_PARAM_INT, OFF(prefilter_iterations), 1, 5, NULL, RT },
	{ "noise-model", "depth noise: fixed (depth-noise), auto (measured per frame and region; drives prefilter, normals and denoise), auto-prefilter (drives the prefilter only)", NULL,
	  DAO_PARAM_ENUM, OFF(noise_model), 0, 0, noise_model_names, RT },
	{ "normals", "how normals are derived from depth", NULL,
	  DAO_PARAM_ENUM, OFF(normals), 0, 0, normals_names, RT },
	{ "normal-radius", "footprint of wide normals (noise-model=auto: from the measured noise)", "px",
	  DAO_PARAM_INT, OFF(normal_radius), 1, 8, NULL, RT },
	{ "algorithm", "gtao (ground-truth AO), vbao (visibility bitmask: finite thickness), hbao, ssao, or edl (eye-dome lighting, not AO)", NULL,
	  DAO_PARAM_ENUM, OFF(algorithm), 0, 4, algorithm_names, RT },
	{ "radius", "world-space AO radius", "m",
	  DAO_PARAM_FLOAT, OFF(radius), 0.01, 100.0, NULL, RT },
	{ "falloff", "fraction of the radius over which occluders fade out", NULL,
	  DAO_PARAM_FLOAT, OFF(falloff), 0.0, 1.0, NULL, RT },
	{ "slices", "slice directions per pixel", NULL,
	  DAO_PARAM_INT, OFF(slices), 1, DAO_MAX_SLICES, NULL, RT },
	{ "steps", "horizon samples per side of each slice", NULL,
	  DAO_PARAM_INT, OFF(steps), 1, DAO_MAX_STEPS, NULL, RT },
	{ "thickness", "thin-occluder heuristic: pull of later, lower samples on the horizon (0 = surfaces infinitely thick)", NULL,
	  DAO_PARAM_FLOAT, OFF(thickness), 0.0, 1.0, NULL, RT },
	{ "max-screen-radius", "cap of the radius projected on screen", "px",
	  DAO_PARAM_FLOAT, OFF(max_screen_radius), 1.0, 4096.0, NULL, RT },
	{ "min-screen-radius", "below this projected radius the pixel is left open", "px",
	  DAO_PARAM_FLOAT, OFF(min_screen_radius), 0.0, 64.0, NULL, RT },
	{ "distribution-power", "sample spacing t^power; > 1 packs samples near the pixel", NULL,
	  DAO_PARAM_FLOAT, OFF(distribution_power), 1.0, 4.0, NULL, RT },
	{ "noise", "rotation of slices and jitter of steps: tile (4x4, the fast kernel), or per pixel ign, r2; none", NULL,
	  DAO_PARAM_ENUM, OFF(noise), 0, 0, noise_names, RT },
	{ "final-power", "visibility is raised to this power", NULL,
	  DAO_PARAM_FLOAT, OFF(final_power), 0.1, 8.0, NULL, RT },
	{ "albedo", "multi-bounce fit (Jimenez 2016) for this albedo; 0 = off", NULL,
	  DAO_PARAM_FLOAT, OFF(albedo), 0.0, 0.95, NULL, RT },
	{ "invalid-value", "visibility written where there is no depth", NULL,
	  DAO_PARAM_FLOAT, OFF(invalid_value), 0.0, 1.0, NULL, RT },
	{ "strength", "hbao, ssao, edl: visibility = 1 - strength x occlusion", NULL,
	  DAO_PARAM_FLOAT, OFF(strength), 0.0, 10.0, NULL, RT },
	{ "hbao-bias", "hbao: tangent bias angle; hides self-occlusion of flat surfaces", "deg",
	  DAO_PARAM_FLOAT, OFF(hbao_bias), 0.0, 60.0, NULL, RT },
	{ "ssao-min", "ssao: a sample is occluded when the surface is in front of it by more than this", "m",
	  DAO_PARAM_FLOAT, OFF(ssao_min), 0.0, 1.0, NULL, RT },
	{ "ssao-max", "ssao: ... and by less than this (farther surfaces are not its occluders)", "m",
	  DAO_PARAM_FLOAT, OFF(ssao_max), 0.001, 100.0, NULL, RT },
	{ "edl-radius", "edl: distance of the neighbours compared", "px",
	  DAO_PARAM_FLOAT, OFF(edl_radius), 0.5, 16.0, NULL, RT },
	{ "vbao-thickness", "vbao: thickness assumed behind every visible surface", "m",
	  DAO_PARAM_FLOAT, OFF(vbao_thickness), 0.001, 10.0, NULL, RT },
	{ "vbao-thickness-mode", "vbao: constant (vbao-thickness behind every surface) or image (each surface's visible extent, at most vbao-thickness-max)", NULL,
	  DAO_PARAM_ENUM, OFF(vbao_thickness_mode), 0, 0, vbao_thickness_names, RT },
	{ "vbao-thickness-max", "vbao, vbao-thickness-mode=image: upper bound of the thickness estimated from the image", "m",
	  DAO_PARAM_FLOAT, OFF(vbao_thickness_max), 0.001, 10.0, NULL, RT },
	{ "temporal", "streams: share of the per-pixel AO history in each output (0 = off; 0.8 settles in ~5 frames)", NULL,
	  DAO_PARAM_FLOAT, OFF(temporal), 0.0, 0.98, NULL, RT },
	{ "temporal-reject", "streams: the AO history of a pixel is dropped where its depth changed by more than this share", NULL,
	  DAO_PARAM_FLOAT, OFF(temporal_reject), 0.001, 1.0, NULL, RT },
	{ "depth-temporal", "streams: share of the per-pixel 1/z history in the depth, before the prefilter (0 = off; streams of the CLI and daemon: 0.8)", NULL,
	  DAO_PARAM_FLOAT, OFF(depth_temporal), 0.0, 0.98, NULL, RT },
	{ "depth-temporal-reject", "streams: the depth history of a pixel restarts where a sample differs from it by more than this many sigma of the noise model", NULL,
	  DAO_PARAM_FLOAT, OFF(depth_temporal_reject), 0.5, 100.0, NULL, RT },
	{ "depth-temporal-persist", "streams: frames a pixel that lost its depth keeps the filtered value (0 = never invent depth)", "frames",
	  DAO_PARAM_INT, OFF(depth_temporal_persist), 0, 30, NULL, RT },
	{ "noise-interval", "noise-model=auto: frames between full measurements of the noise, with a check of every frame that measures the cells the scene moved in, and all after a cut (1 = every frame; streams of the CLI and daemon: 15)", "frames",
	  DAO_PARAM_INT, OFF(noise_interval), 1, 3600, NULL, RT },
	{ "threads", "threads per context (0 = one per available CPU)", NULL,
	  DAO_PARAM_INT, OFF(threads), 0, 256, NULL, RT },
	{ "simd", "kernels: auto (best for this CPU), reference (scalar oracle) or an instruction set", NULL,
	  DAO_PARAM_ENUM, OFF(simd), 0, 0, dao_simd_names, RT },
	{ "denoise", "spatial filter of the AO", NULL,
	  DAO_PARAM_ENUM, OFF(denoise), 0, 0, denoise_names, RT },
	{ "denoise-radius", "radius of the bilateral denoise", "px",
	  DAO_PARAM_INT, OFF(denoise_radius), 1, 16, NULL, RT },
	{ "denoise-sharpness", "depth tolerance of the denoise in units of the depth noise", NULL,
	  DAO_PARAM_FLOAT, OFF(denoise_sharpness), 0.1, 100.0, NULL, RT },
	{ "shade", "shaded image: lambert head light, depth colormap, or AO alone", NULL,
	  DAO_PARAM_ENUM, OFF(shade), 0, 0, shade_names, SH },
	{ "near", "colormap near depth; 0 = nearest depth in the frame", "m",
	  DAO_PARAM_FLOAT, OFF(near_m), 0.0, 1000.0, NULL, SH },
	{ "far", "colormap far depth; 0 = farthest depth in the frame", "m",
	  DAO_PARAM_FLOAT, OFF(far_m), 0.0, 1000.0, NULL, SH },
	{ "shade-power", "shaded = mix(occlusion colour, colour, AO^power)", NULL,
	  DAO_PARAM_FLOAT, OFF(shade_power), 0.0, 8.0, NULL, SH },
	{ "occlusion-color", "colour of full occlusion, RRGGBB", NULL,
	  DAO_PARAM_COLOR, OFF(occlusion_color), 0, 0xffffff, NULL, SH },
};

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
