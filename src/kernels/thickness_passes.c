/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image (thickness.h): the setup and the estimate's two
 * passes.  The rows and the columns are split into runs (same_mask, line),
 * each run's estimate made (thickness_run.c) and its pixels given their
 * values; the column pass also writes the kernel's plane of halves.  Two
 * passes, O(1) per pixel, no allocation.
 */
#include "kernels/thickness_memo.h"

#include "core/half.h"
#include "core/math_util.h"
#include "core/multiversion.h"
#include "kernels/gtao_planes.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __SSE2__
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>
#endif

void dao_thickness_setup_init(struct dao_thickness_setup *t, const struct dao_camera *cam,
			      float max)
{
	t->width = (int)cam->width;
	t->height = (int)cam->height;
	t->ax = cam->ax;
	t->ay = cam->ay;
	t->bx = cam->bx;
	t->by = cam->by;
	t->max = max;
	t->crease_cos = cosf(DAO_SLAB_CREASE_DEG * (DAO_PI_F / 180.0f));
	t->spacing = 0.0f;
	t->noise_k = 0.0f;
	t->fill_px = DAO_THICKNESS_FILL_PX;
}

void dao_thickness_setup_rounding(struct dao_thickness_setup *t, float scale)
{
	float a = (scale - DAO_SLAB_ROUND_FROM) / (DAO_SLAB_ROUND_TO - DAO_SLAB_ROUND_FROM);
	a = a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f;
	const float deg = DAO_SLAB_CREASE_DEG + a * (DAO_SLAB_CREASE_ROUNDED_DEG - DAO_SLAB_CREASE_DEG);
	t->crease_cos = cosf(deg * (DAO_PI_F / 180.0f));
}

void dao_thickness_setup_noise(struct dao_thickness_setup *t, float scale, float sigma)
{
	t->noise_k = scale > DAO_SLAB_ROUND_FROM ? DAO_THICKNESS_NOISE_TOL * sigma : 0.0f;
	t->fill_px = scale <= (float)DAO_THICKNESS_FILL_PX ? DAO_THICKNESS_FILL_PX : 0;
}

static void fb_memo_clear(struct fb_memo *m)
{
	for (int i = 0; i < 1 << FB_MEMO_BITS; i++)
		m->e[i].dir = 0;
}

/* The run's pixels get its values (take_min: where smaller than what they hold). */
static void run(const struct line_geom *g, float *thick, int n, int s, int e, int take_min)
{
	struct run_est r;
	run_estimate(g, n, s, e, &r);
	const size_t step = g->step;
	if (r.slabs || r.bounds) {
		for (int k = s; k <= e; k++) {
			const float vk = face_bound_value(g, r.bounds, r.bound, k,
							  r.slabs ? run_slab_value(g, &r, k) : r.value);
			float *o = &thick[(size_t)k * step];
			if (!take_min || vk < *o)
				*o = vk;
		}
	} else if (take_min) {
		for (int k = s; k <= e; k++) {
			float *o = &thick[(size_t)k * step];
			if (r.value < *o)
				*o = r.value;
		}
	} else {
		for (int k = s; k <= e; k++)
			thick[(size_t)k * step] = r.value;
	}
}

/* One line of n pixels (run), holes: the bound (take_min: left alone). */
static void line(const struct dao_thickness_setup *t, const float *z, float *thick, int n,
		 size_t step, float u0, float v0, float du, float dv, int take_min,
		 struct fb_memo *memo)
{
	const struct line_geom g = { t, z, step, u0, v0, du, dv, memo };
	int i = 0;
	while (i < n) {
		const float zs = z[(size_t)i * step];
		if (!(zs > 0.0f)) {
			if (!take_min)
				thick[(size_t)i * step] = t->max;
			i++;
			continue;
		}
		const int s = i;
		while (i + 1 < n && same_surface(z[(size_t)i * step], z[(size_t)(i + 1) * step]))
			i++;
		run(&g, thick, n, s, i, take_min);
		i++;
	}
}

/*
 * The same-surface test between a[c] and b[c] for n <= 64 pixels side by side:
 * bit c of the result.  With SSE2 four at a time (the same comparisons and
 * the one product: min(a, b) as a < b ? a : b, the same bits).
 */
static inline uint64_t same_mask(const float *a, const float *b, int n)
{
	uint64_t m = 0;
	int c = 0;
#ifdef __SSE2__
	const __m128 zero = _mm_setzero_ps(), jump = _mm_set1_ps(DAO_THICKNESS_JUMP);
	const __m128 sign = _mm_set1_ps(-0.0f);
	for (; c + 4 <= n; c += 4) {
		const __m128 va = _mm_loadu_ps(a + c), vb = _mm_loadu_ps(b + c);
		const __m128 d = _mm_andnot_ps(sign, _mm_sub_ps(va, vb));
		const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(va, zero), _mm_cmpgt_ps(vb, zero)),
					     _mm_cmple_ps(d, _mm_mul_ps(jump, _mm_min_ps(va, vb))));
		m |= (uint64_t)_mm_movemask_ps(ok) << c;
	}
#endif
	for (; c < n; c++)
		m |= (uint64_t)same_surface(a[c], b[c]) << c;
	return m;
}

/* the bits below n (1 <= n <= 64) */
static inline uint64_t low_bits(int n)
{
	return n >= 64 ? ~(uint64_t)0 : ((uint64_t)1 << n) - 1;
}

/* line() for rows, its runs' ends found a chunk of pixels at a time (same_mask). */
void dao_thickness_rows(const struct dao_thickness_setup *t, const float *z, float *thick,
			int y0, int y1)
{
	const int w = t->width;
	struct fb_memo memo;
	fb_memo_clear(&memo);
	for (int y = y0; y < y1; y++) {
		const size_t o = (size_t)y * w;
		const struct line_geom g = { t, z + o, 1, 0.0f, (float)y, 1.0f, 0.0f, &memo };
		int start = 0;
		for (int xc = 0; xc < w; xc += 64) {
			const int n = w - xc < 64 ? w - xc : 64;
			/* (the row's last pixel has no next: it ends its run) */
			const int last = xc + n == w;
			const float *zc = z + o + xc;
			uint64_t ends = ~same_mask(zc, zc + 1, last ? n - 1 : n) & low_bits(n);
			while (ends) {
				const int x = xc + __builtin_ctzll(ends);
				ends &= ends - 1;
				if (z[o + x] > 0.0f)
					run(&g, thick + o, w, start, x, 0);
				else
					thick[o + x] = t->max;
				start = x + 1;
			}
		}
	}
}

void dao_thickness_rows_ref(const struct dao_thickness_setup *t, const float *z, float *thick,
			    int y0, int y1)
{
	/* (no memo: each face bound made from the pixels) */
	for (int y = y0; y < y1; y++) {
		const size_t o = (size_t)y * t->width;
		line(t, z + o, thick + o, t->width, 1, 0.0f, (float)y, 1.0f, 0.0f, 0, NULL);
	}
}

void dao_thickness_cols_ref(const struct dao_thickness_setup *t, const float *z, float *thick,
			    int x0, int x1)
{
	for (int x = x0; x < x1; x++)
		line(t, z + x, thick + x, t->height, (size_t)t->width, (float)x, 0.0f, 0.0f, 1.0f, 1,
		     NULL);
}

/*
 * The column pass over a block of columns side by side, in two sweeps that
 * read and write whole rows of the block (a column walk, a row stride per
 * pixel, missed the cache at nearly every pixel of the plane).  Down the
 * rows, the same-surface test between two rows is made for the block's
 * columns at once, and where a column's run ends its value is made
 * (run_estimate) and left in the scratch at the run's last row: the other
 * rows of the run hold RUN_INSIDE, a hole +inf (it leaves the pixel alone);
 * a run with slabs leaves each of its pixels' own values.  Up the rows, each
 * column carries the value of the run it is in (a run's last row is met
 * first), and the plane takes the smaller one.  The same runs and arithmetic
 * as line(): the result is dao_thickness_cols_ref's.
 */
#define RUN_INSIDE (-1.0f)

_Static_assert(DAO_THICKNESS_COL_BLOCK <= 64, "a block's ends are the bits of a uint64_t");

/* The row's columns c < n: v[c] = the run's value from sc[c] unless RUN_INSIDE,
 * thick[c] = the smaller of it and v[c] */
DAO_MULTIVERSION
static void cols_put(const float *restrict sc, float *restrict thick, float *restrict v, int n)
{
	for (int c = 0; c < n; c++) {
		const float r = sc[c];
		const float vc = r == RUN_INSIDE ? v[c] : r;
		const float o = thick[c];
		v[c] = vc;
		thick[c] = vc < o ? vc : o;
	}
}

/* cols_put for n = 4 m columns from a multiple of 4 on, each also to its entry
 * of its phase's row of the thickness plane, as a half: column 4 j + q to o[q][j]
 * (with SSE2 16 columns at a time, a 4 x 4 transpose: the same selections and
 * minima, the same halves; HALF4: 4 floats to 4 halves in the low 64 bits) */
#define COLS_PUT_SPLIT_SSE2(HALF4)                                                          \
	const __m128 inside = _mm_set1_ps(RUN_INSIDE);                                     \
	for (; j + 4 <= m; j += 4) {                                                       \
		__m128 r[4];                                                               \
		for (int i = 0; i < 4; i++) {                                              \
			const int c = 4 * (j + i);                                         \
			const __m128 sv = _mm_loadu_ps(sc + c);                            \
			const __m128 in = _mm_cmpeq_ps(sv, inside);                        \
			const __m128 vc = _mm_or_ps(_mm_and_ps(in, _mm_loadu_ps(v + c)),    \
						    _mm_andnot_ps(in, sv));                \
			_mm_storeu_ps(v + c, vc);                                          \
			r[i] = _mm_min_ps(vc, _mm_loadu_ps(thick + c)); /* vc < o ? vc : o */ \
			_mm_storeu_ps(thick + c, r[i]);                                    \
		}                                                                          \
		_MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);                                 \
		_mm_storel_epi64((__m128i *)(o0 + j), HALF4(r[0]));                       \
		_mm_storel_epi64((__m128i *)(o1 + j), HALF4(r[1]));                       \
		_mm_storel_epi64((__m128i *)(o2 + j), HALF4(r[2]));                       \
		_mm_storel_epi64((__m128i *)(o3 + j), HALF4(r[3]));                       \
	}

static inline void cols_put_split_tail(const float *restrict sc, float *restrict thick,
				       float *restrict v, uint16_t *restrict o0,
				       uint16_t *restrict o1, uint16_t *restrict o2,
				       uint16_t *restrict o3, int j, int m)
{
	for (; j < m; j++) {
		float r[4];
		for (int q = 0; q < 4; q++) {
			const int c = 4 * j + q;
			const float vc = sc[c] == RUN_INSIDE ? v[c] : sc[c];
			const float o = thick[c];
			v[c] = vc;
			r[q] = vc < o ? vc : o;
			thick[c] = r[q];
		}
		o0[j] = dao_half_from_float(r[0]);
		o1[j] = dao_half_from_float(r[1]);
		o2[j] = dao_half_from_float(r[2]);
		o3[j] = dao_half_from_float(r[3]);
	}
}

DAO_MULTIVERSION
static void cols_put_split(const float *restrict sc, float *restrict thick, float *restrict v,
			   uint16_t *restrict o0, uint16_t *restrict o1, uint16_t *restrict o2,
			   uint16_t *restrict o3, int m)
{
	int j = 0;
#ifdef __SSE2__
	COLS_PUT_SPLIT_SSE2(dao_half_from_ps_sse2)
#endif
	cols_put_split_tail(sc, thick, v, o0, o1, o2, o3, j, m);
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define HAVE_SPLIT_F16C 1
/* the same with the conversion of F16C (which rounds the same), for CPUs that
 * have it (__builtin_cpu_supports) */
__attribute__((target("f16c"))) static inline __m128i half4_f16c(__m128 r)
{
	return _mm_cvtps_ph(r, 0); /* to nearest even */
}

__attribute__((target("f16c"))) static void
cols_put_split_f16c(const float *restrict sc, float *restrict thick, float *restrict v,
		    uint16_t *restrict o0, uint16_t *restrict o1, uint16_t *restrict o2,
		    uint16_t *restrict o3, int m)
{
	int j = 0;
	COLS_PUT_SPLIT_SSE2(half4_f16c)
	cols_put_split_tail(sc, thick, v, o0, o1, o2, o3, j, m);
}
#else
#define HAVE_SPLIT_F16C 0
#endif

void dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			float *scratch, struct dao_gtao_planes *pl, int x0, int x1)
{
	const size_t w = (size_t)t->width;
	const int h = t->height;
	const size_t bs = DAO_THICKNESS_COL_BLOCK;
#if HAVE_SPLIT_F16C
	const int f16c = __builtin_cpu_supports("f16c");
#endif
	struct fb_memo memo;
	fb_memo_clear(&memo);
	for (int xb = x0; xb < x1; xb += DAO_THICKNESS_COL_BLOCK) {
		const int nb = x1 - xb < DAO_THICKNESS_COL_BLOCK ? x1 - xb : DAO_THICKNESS_COL_BLOCK;
		int start[DAO_THICKNESS_COL_BLOCK];
		for (int c = 0; c < nb; c++)
			start[c] = 0;
		for (int y = 0; y < h; y++) {
			const float *za = z + (size_t)y * w + xb;
			float *sr = scratch + (size_t)y * bs;
			uint64_t ends = low_bits(nb);
			if (y + 1 < h)
				ends &= ~same_mask(za, za + w, nb);
			for (int c = 0; c < nb; c++)
				sr[c] = RUN_INSIDE;
			/* the rows the way up writes: asked for now, while this sweep reads the
			 * depth (the row pass left them in the other threads' caches) */
			for (int c = 0; c < nb; c += 16)
				__builtin_prefetch(thick + (size_t)y * w + xb + c, 1, 3);
			if (pl)
				for (int q = 0; q < 4; q++)
					__builtin_prefetch(dao_gtao_thick_row(pl, y, q) + xb / 4, 1, 3);
			while (ends) {
				const int c = __builtin_ctzll(ends);
				ends &= ends - 1;
				/* the run start[c] .. y of column xb + c ends here */
				if (za[c] > 0.0f) {
					const struct line_geom g = { t, z + xb + c, w, (float)(xb + c), 0.0f,
								     0.0f, 1.0f, &memo };
					struct run_est r;
					run_estimate(&g, h, start[c], y, &r);
					if (r.slabs || r.bounds) {
						for (int k = start[c]; k <= y; k++)
							scratch[(size_t)k * bs + c] = face_bound_value(
								&g, r.bounds, r.bound, k,
								r.slabs ? run_slab_value(&g, &r, k) : r.value);
					} else {
						sr[c] = r.value;
					}
				} else {
					sr[c] = INFINITY;
				}
				start[c] = y + 1;
			}
		}
		float v[DAO_THICKNESS_COL_BLOCK];
		for (int c = 0; c < nb; c++)
			v[c] = INFINITY;
		const int split = pl && !(xb & 3) && !(nb & 3);
		for (int y = h - 1; y >= 0; y--) {
			const float *sr = scratch + (size_t)y * bs;
			float *tr = thick + (size_t)y * w + xb;
			if (split) {
				uint16_t *o[4];
				for (int q = 0; q < 4; q++)
					o[q] = (uint16_t *)dao_gtao_thick_row(pl, y, q) + xb / 4;
#if HAVE_SPLIT_F16C
				if (f16c)
					cols_put_split_f16c(sr, tr, v, o[0], o[1], o[2], o[3],
							    nb / 4);
				else
#endif
					cols_put_split(sr, tr, v, o[0], o[1], o[2], o[3], nb / 4);
			} else {
				cols_put(sr, tr, v, nb);
				if (pl)
					dao_gtao_planes_fill_thickness_cols(pl, thick, y, y + 1, xb,
									    xb + nb);
			}
		}
	}
}
