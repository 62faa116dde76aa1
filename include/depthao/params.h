/* SPDX-License-Identifier: MIT */
/*
 * Parameters of the AO pipeline, and a table that describes them.
 *
 * `struct dao_params` holds every setting of a context.  The table returned
 * by dao_param_table() names each field with its type, unit, range and help
 * text, so command-line flags, config keys, run-time `set` commands and help
 * output are all generated from one place (as FFmpeg's AVOption tables).  The
 * defaults are those of the presets: dao_params_init().
 */
#ifndef DEPTHAO_PARAMS_H
#define DEPTHAO_PARAMS_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The largest `slices` and `steps` (the parameter table's limits; the
 * kernels' per-slice and per-step arrays are sized by them). */
#define DAO_MAX_SLICES 32
/* The largest `steps`. */
#define DAO_MAX_STEPS 64

/* Quality presets (dao_params_init()). */
enum dao_quality {
	DAO_QUALITY_LOW = 0,
	DAO_QUALITY_MEDIUM,   /* the default: meets the accuracy bars in README.md */
	DAO_QUALITY_HIGH,
	DAO_QUALITY_ULTRA,
	DAO_QUALITY_COUNT,
	DAO_QUALITY_DEFAULT = DAO_QUALITY_MEDIUM,
};

/* The AO algorithm (docs/algorithms.md). */
enum dao_algorithm {
	DAO_ALGORITHM_GTAO = 0, /* ground-truth AO: horizons per slice, cosine-weighted integral */
	DAO_ALGORITHM_HBAO,     /* horizon-based AO (Bavoil 2008): tangent bias, W(r) = 1 - r^2 */
	DAO_ALGORITHM_SSAO,     /* Crytek-style hemisphere kernel with a depth range check */
	DAO_ALGORITHM_EDL,      /* eye-dome lighting: depth-only shading, not AO */
	DAO_ALGORITHM_VBAO,     /* visibility bitmask (Therrien et al. 2023): finite thickness */
	DAO_ALGORITHM_NONE,     /* depth only: decode, noise, temporal depth, prefilter; no
				 * normals, AO or shading (dao_context_get_depth) */
};

/* Where VBAO's thickness of each occluder comes from (docs/algorithms.md). */
enum dao_vbao_thickness_mode {
	DAO_VBAO_THICKNESS_CONSTANT = 0, /* vbao_thickness behind every surface */
	DAO_VBAO_THICKNESS_IMAGE,        /* each surface's visible extent, at most
					  * vbao_thickness_max */
};

/* Depth prefilters (`prefilter`). */
enum dao_prefilter {
	DAO_PREFILTER_NONE = 0,
	DAO_PREFILTER_BILATERAL,  /* edge-preserving smoothing scaled to sensor noise */
	DAO_PREFILTER_DOMAIN,     /* recursive edge-preserving filter (domain transform,
				   * Gastal & Oliveira 2011): cost independent of its scale */
};

/* Where the depth noise the filters are scaled to comes from. */
enum dao_noise_model {
	DAO_NOISE_MODEL_FIXED = 0,      /* depth_noise: sigma(z) = depth_noise z^2 */
	DAO_NOISE_MODEL_AUTO,           /* measured in every frame, per region; drives the
					 * prefilter, the normals' footprint and the denoise */
	DAO_NOISE_MODEL_AUTO_PREFILTER, /* measured, drives the prefilter only */
};

/* How the temporal depth filter follows the camera's motion (`depth-temporal-motion`). */
enum dao_depth_motion {
	DAO_DEPTH_MOTION_OFF = 0, /* the history stays where it was (a still camera) */
	DAO_DEPTH_MOTION_ICP,     /* the motion estimated from the depth (point-to-plane ICP)
				   * carries the history into the new view; where the
				   * estimate is refused, as OFF */
	DAO_DEPTH_MOTION_SOURCE,  /* the motion between the poses the caller gives
				   * (dao_context_set_pose) carries the history, as is;
				   * without a pose for this frame and the last, as OFF */
	DAO_DEPTH_MOTION_SOURCE_ICP, /* ICP seeded with the given poses' motion; without
				      * them, as ICP */
};

/* How normals are derived from depth (`normals`). */
enum dao_normals {
	DAO_NORMALS_SMALLER_DELTA = 0, /* per axis the smaller one-sided difference (1 px) */
	DAO_NORMALS_WIDE,              /* same, over a wider footprint (normal_radius px) */
};

/* Per-pixel rotation of the slices and jitter of the steps (`noise`). */
enum dao_noise {
	DAO_NOISE_IGN = 0,  /* interleaved gradient noise (Jimenez 2014) */
	DAO_NOISE_R2,       /* R2 low-discrepancy sequence (Roberts 2018) */
	DAO_NOISE_NONE,     /* same directions at every pixel */
	DAO_NOISE_TILE,     /* a 4x4 tile of stratified values: the fast path of the
			     * optimised GTAO (pixels of a tile phase share directions) */
};

/* AO denoise filters (`denoise`). */
enum dao_denoise {
	DAO_DENOISE_NONE = 0,
	DAO_DENOISE_PLANE,      /* 5x5, weights against the extrapolated depth plane */
	DAO_DENOISE_BILATERAL,  /* separable cross-bilateral (Gaussian x depth threshold) */
};

/* Which kernels run: the scalar reference (the correctness oracle) or an
 * optimised build for an instruction set; AUTO = the best this CPU has. */
enum dao_simd {
	DAO_SIMD_AUTO = 0,
	DAO_SIMD_REFERENCE,  /* plain scalar C, libm trigonometry: the oracle */
	DAO_SIMD_GENERIC,    /* portable vector code (compiler vector extensions) */
	DAO_SIMD_SSE41,
	DAO_SIMD_AVX2,       /* AVX2 + FMA */
	DAO_SIMD_AVX512,     /* AVX-512 F/VL/DQ/BW at 16 lanes: masks, 32 registers */
	DAO_SIMD_COUNT,
};

/* How the shaded image is coloured (`shade`). */
enum dao_shade {
	DAO_SHADE_LAMBERT = 0,  /* n . l with a head light, times AO */
	DAO_SHADE_TURBO,        /* depth colormap times AO */
	DAO_SHADE_JET,
	DAO_SHADE_GRAY,
	DAO_SHADE_AO,           /* AO alone as gray */
};

/* Every AO parameter; the table (dao_param_table()) describes each field. */
struct dao_params {
	/* sizeof(struct dao_params) as the program that filled it was built, set by
	 * dao_params_init(): a program built against an older depthao passes a
	 * shorter struct, and the library takes the defaults for the fields it
	 * lacks (fields are only ever added at the end; README "ABI policy") */
	uint32_t size;

	/* depth input */
	float depth_min;          /* m; nearer = no data */
	float depth_max;          /* m; farther = no data */
	int prefilter;            /* enum dao_prefilter (default: DOMAIN) */
	float depth_noise;        /* sensor noise model: sigma(z) = depth_noise * z^2 (1/m),
				   * with noise_model FIXED */
	int prefilter_radius;     /* px, bilateral */
	float prefilter_scale;    /* domain: spatial scale sigma_s, px */
	float prefilter_range;    /* domain: range scale in units of the local noise */
	int prefilter_iterations; /* domain: vertical + horizontal passes */
	int noise_model;          /* enum dao_noise_model (default: AUTO, the noise measured in
				   * every frame; FIXED: depth_noise, prefilter_scale and
				   * normal_radius as given) */
	int normals;              /* enum dao_normals */
	int normal_radius;        /* px, for DAO_NORMALS_WIDE with noise_model FIXED or
				   * AUTO_PREFILTER (AUTO: from the measured noise) */

	/* AO */
	int algorithm;            /* enum dao_algorithm */
	float radius;             /* world-space radius R, m */
	float falloff;            /* fraction of R over which occluders fade out */
	int slices;               /* slice directions per pixel */
	int steps;                /* samples per side of each slice */
	float thickness;          /* thin-occluder compensation, 0 = infinitely thick */
	float max_screen_radius;  /* cap of the projected radius, px */
	float min_screen_radius;  /* below this projected radius, no search (visibility 1), px */
	float distribution_power; /* sample spacing: t^power, > 1 packs samples near the pixel */
	int noise;                /* enum dao_noise */
	float final_power;        /* visibility^power */
	float albedo;             /* multi-bounce fit (Jimenez 2016), 0 = off */
	float invalid_value;      /* visibility written for pixels without depth */
	float strength;           /* HBAO, SSAO, EDL: visibility = 1 - strength * occlusion */
	float hbao_bias;          /* HBAO tangent bias angle, degrees */
	float ssao_min, ssao_max; /* SSAO: a sample counts when the surface is this far in front, m */
	float edl_radius;         /* EDL neighbour distance, px */
	float vbao_thickness;     /* VBAO, mode CONSTANT: assumed thickness of what the depth
				   * image shows, m */
	float temporal;           /* AO: share of the history in each output (0 = off), streams */
	float temporal_reject;    /* AO history dropped where depth changed by more than this share */
	float depth_temporal;     /* depth: share of the 1/z history in each frame (0 = off), streams */
	float depth_temporal_reject; /* depth history restarts beyond this many sigma of the noise */
	int depth_temporal_persist;  /* frames a pixel without data keeps its filtered depth */
	int threads;              /* worker threads of a context, 0 = one per available CPU */
	int simd;                 /* enum dao_simd */

	/* denoise */
	int denoise;              /* enum dao_denoise */
	int denoise_radius;       /* px, bilateral */
	float denoise_sharpness;  /* depth tolerance of the denoise, in units of sigma(z) */

	/* shading */
	int shade;                /* enum dao_shade */
	float near_m, far_m;      /* colormap range, m; 0 = from the frame's depth */
	float shade_power;        /* shaded = mix(occlusion_color, color, AO^shade_power) */
	uint32_t occlusion_color; /* 0xRRGGBB */

	/* added after the first layout (a caller's struct may end before them) */
	int vbao_thickness_mode;  /* enum dao_vbao_thickness_mode (default IMAGE) */
	float vbao_thickness_max; /* VBAO, mode IMAGE: upper bound of the estimate, m */
	int noise_interval;       /* noise_model AUTO*: frames between full measurements of the
				   * noise (1 = every frame, the presets; streams:
				   * dao_params_stream_defaults), with a check of every frame
				   * that measures again where the scene moved */
	int depth_temporal_motion; /* enum dao_depth_motion (default OFF) */
	int depth_fill;           /* filtered depth output (dao_context_get_depth) only: holes
				   * of at most this many px along a row filled where both
				   * sides lie on one surface (0 = off, the default) */
};

/* Types of the parameters in the table. */
enum dao_param_type {
	DAO_PARAM_FLOAT = 0,  /* float field, range [min, max] */
	DAO_PARAM_INT,        /* int field, range [min, max] */
	DAO_PARAM_ENUM,       /* int field, one of enum_names (index) */
	DAO_PARAM_COLOR,      /* uint32_t 0xRRGGBB field, written "RRGGBB" or "#RRGGBB" */
};

#define DAO_PARAM_RUNTIME   (1u << 0) /* may change while a stream runs */
#define DAO_PARAM_SHADING   (1u << 1) /* affects only the shaded image */

/* One parameter of the table: its name, help, unit, type, field and range. */
struct dao_param_info {
	const char *name;              /* "radius": flag --radius, config key radius */
	const char *help;              /* one line */
	const char *unit;              /* "m", "px", NULL */
	/* how the field is stored and parsed */
	enum dao_param_type type;
	size_t offset;                 /* offsetof(struct dao_params, field) */
	double min, max;               /* inclusive range (FLOAT, INT) */
	const char *const *enum_names; /* NULL-terminated (ENUM) */
	unsigned flags;                /* DAO_PARAM_* */
};

/* The table of all parameters; *count receives its length. */
DAO_API const struct dao_param_info *dao_param_table(size_t *count);

/* The entry called `name` (dashes and underscores are equivalent), or NULL. */
DAO_API const struct dao_param_info *dao_param_find(const char *name);

/* Name of a quality preset ("low", ...), NULL if out of range. */
DAO_API const char *dao_quality_name(enum dao_quality q);

/* Parses "low|medium|high|ultra|default". Returns 0 or -EINVAL. */
DAO_API int dao_quality_parse(const char *name, enum dao_quality *q, struct dao_error *err);

/* sizeof(struct dao_params) of this library, for bindings that cannot see the header. */
DAO_API size_t dao_params_size(void);

/*
 * Fills `p`, a struct dao_params of `size` bytes, with a quality preset and
 * sets p->size.  -EINVAL if `size` is smaller than the first struct that
 * carried a size or larger than this library's.  Programs call
 * dao_params_init() below, which passes their own sizeof; bindings that
 * cannot see the header pass dao_params_size().
 */
DAO_API int dao_params_init_sized(struct dao_params *p, size_t size, enum dao_quality q);

/* Fills `p` with a quality preset. */
static inline void dao_params_init(struct dao_params *p, enum dao_quality q)
{
	(void)dao_params_init_sized(p, sizeof(*p), q);
}

/*
 * Turns on what suits a stream of consecutive frames from one camera (a
 * recording, a device): the temporal depth filter (depth-temporal 0.8) and
 * the noise measured every few frames rather than in each (noise-interval).
 * The presets leave it off: a library user decides whether frames follow
 * each other.  depthaod and `depthao process` on a recording or device call
 * this before applying the user's settings.
 */
DAO_API void dao_params_stream_defaults(struct dao_params *p);

/*
 * Sets one parameter from text, checking type and range.  On error nothing
 * changes and the message names the parameter, the value and the valid range.
 */
DAO_API int dao_params_set(struct dao_params *p, const char *name, const char *value,
		   struct dao_error *err);

/* Writes the value of one parameter as text ("0.5", "bilateral", "000000"). */
DAO_API int dao_params_get(const struct dao_params *p, const char *name, char *buf, size_t len,
		   struct dao_error *err);

/* Checks every field against its range and the fields against each other. */
DAO_API int dao_params_validate(const struct dao_params *p, struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
