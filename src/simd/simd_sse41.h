/* SPDX-License-Identifier: MIT */
/* SIMD vocabulary for SSE4.1: 4 float lanes (no gather instruction: lane loads). */
#ifndef DAO_SIMD_SSE41_H
#define DAO_SIMD_SSE41_H

#include <smmintrin.h>
#include <stdint.h>
#include <string.h>

#include "core/half.h"

#define VN 4
#define DAO_SIMD_NAME "sse4.1"

typedef __m128 vf;
typedef __m128i vi;
typedef __m128 vm;

static inline vf v_set1(float a) { return _mm_set1_ps(a); }
static inline vf v_zero(void) { return _mm_setzero_ps(); }
static inline vf v_iota(void) { return _mm_setr_ps(0, 1, 2, 3); }
static inline vf v_load(const float *p) { return _mm_loadu_ps(p); }
/* VN IEEE halves (core/half.h) as floats, exact, lane by lane */
static inline vf v_load_h(const uint16_t *p)
{
	return _mm_setr_ps(dao_half_to_float(p[0]), dao_half_to_float(p[1]), dao_half_to_float(p[2]),
			   dao_half_to_float(p[3]));
}
static inline void v_store(float *p, vf a) { _mm_storeu_ps(p, a); }
static inline vf v_add(vf a, vf b) { return _mm_add_ps(a, b); }
static inline vf v_sub(vf a, vf b) { return _mm_sub_ps(a, b); }
static inline vf v_mul(vf a, vf b) { return _mm_mul_ps(a, b); }
static inline vf v_div(vf a, vf b) { return _mm_div_ps(a, b); }
static inline vf v_fma(vf a, vf b, vf c) { return _mm_add_ps(_mm_mul_ps(a, b), c); }
static inline vf v_fnma(vf a, vf b, vf c) { return _mm_sub_ps(c, _mm_mul_ps(a, b)); } /* c - a b */
static inline vf v_min(vf a, vf b) { return _mm_min_ps(a, b); }
static inline vf v_max(vf a, vf b) { return _mm_max_ps(a, b); }
static inline vf v_sqrt(vf a) { return _mm_sqrt_ps(a); }
static inline vf v_abs(vf a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
static inline vf v_neg(vf a) { return _mm_xor_ps(_mm_set1_ps(-0.0f), a); }
static inline vf v_floor(vf a) { return _mm_floor_ps(a); }
static inline vf v_round(vf a) { return _mm_round_ps(a, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC); }

/* 1/a and 1/sqrt(a): estimate + one Newton step (relative error below 3e-7), a > 0 */
static inline vf v_rcp(vf a)
{
	vf r = _mm_rcp_ps(a);
	return _mm_mul_ps(r, _mm_sub_ps(_mm_set1_ps(2.0f), _mm_mul_ps(a, r)));
}
/* 1/a, hardware estimate only (relative error < 3.7e-4); 1/0 = inf */
static inline vf v_rcp_fast(vf a) { return _mm_rcp_ps(a); }
/* 1/sqrt(a), hardware estimate only (relative error < 3.7e-4) */
static inline vf v_rsqrt_fast(vf a) { return _mm_rsqrt_ps(a); }
static inline vf v_rsqrt(vf a)
{
	vf r = _mm_rsqrt_ps(a);
	vf ar2 = _mm_mul_ps(_mm_mul_ps(a, r), r);
	return _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(0.5f), r), _mm_sub_ps(_mm_set1_ps(3.0f), ar2));
}

static inline vm v_lt(vf a, vf b) { return _mm_cmplt_ps(a, b); }
static inline vm v_le(vf a, vf b) { return _mm_cmple_ps(a, b); }
static inline vm v_gt(vf a, vf b) { return _mm_cmpgt_ps(a, b); }
static inline vm v_ge(vf a, vf b) { return _mm_cmpge_ps(a, b); }
static inline vm v_eq(vf a, vf b) { return _mm_cmpeq_ps(a, b); }
static inline vm m_and(vm a, vm b) { return _mm_and_ps(a, b); }
static inline vm m_or(vm a, vm b) { return _mm_or_ps(a, b); }
static inline vm m_andnot(vm a, vm b) { return _mm_andnot_ps(b, a); }
static inline int m_any(vm a) { return _mm_movemask_ps(a) != 0; }
static inline int m_all(vm a) { return _mm_movemask_ps(a) == 0xf; }
static inline vf v_sel(vm m, vf a, vf b) { return _mm_blendv_ps(b, a, m); }

static inline void vi_store(int32_t *p, vi a) { _mm_storeu_si128((__m128i *)(void *)p, a); }
static inline vi vi_set1(int32_t a) { return _mm_set1_epi32(a); }
static inline vi vi_add(vi a, vi b) { return _mm_add_epi32(a, b); }
static inline vi vi_mul(vi a, vi b) { return _mm_mullo_epi32(a, b); }
static inline vi vi_from_whole(vf a) { return _mm_cvtps_epi32(a); }
/* a rounded to the nearest whole number (ties to even, the default rounding) */
static inline vi vi_from_nearest(vf a) { return _mm_cvtps_epi32(a); }
/* a where m, else 0 (v_sel with 0, as one AND) */
static inline vf v_keep(vm m, vf a) { return _mm_and_ps(m, a); }
static inline vi vi_keep(vm m, vi a) { return _mm_and_si128(_mm_castps_si128(m), a); }
/* whether any bit of a is set */
static inline int vi_any(vi a) { return !_mm_testz_si128(a, a); }
static inline vi vi_sel(vm m, vi a, vi b)
{
	return _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(b), _mm_castsi128_ps(a), m));
}
static inline vi vi_or(vi a, vi b) { return _mm_or_si128(a, b); }
static inline vi vi_andnot(vi a, vi b) { return _mm_andnot_si128(b, a); } /* a & ~b */
/* the n lowest bits set, n in [0, 32]: 2^n - 1 with 2^n made as a float (SSE has
 * no per-lane shift); its conversion gives 0x80000000 for 2^31 (right) and 2^32 */
static inline vi vi_low_bits(vi n)
{
	const __m128i p = _mm_cvttps_epi32(_mm_castsi128_ps(
		_mm_slli_epi32(_mm_add_epi32(n, _mm_set1_epi32(127)), 23)));
	return _mm_or_si128(_mm_sub_epi32(p, _mm_set1_epi32(1)),
			    _mm_cmpeq_epi32(n, _mm_set1_epi32(32)));
}
/* lanes whose bit `bit` (a power of two) is set */
static inline vm m_bit(vi a, int32_t bit)
{
	const __m128i b = _mm_set1_epi32(bit);
	return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(a, b), b));
}
/* lanes with any bit set */
static inline vm m_nonzero(vi a)
{
	return _mm_castsi128_ps(_mm_xor_si128(_mm_cmpeq_epi32(a, _mm_setzero_si128()),
					      _mm_set1_epi32(-1)));
}
/* the OR of all lanes */
static inline uint32_t vi_hor(vi a)
{
	const __m128i o = _mm_or_si128(a, _mm_shuffle_epi32(a, 0x4e));
	return (uint32_t)_mm_cvtsi128_si32(_mm_or_si128(o, _mm_shuffle_epi32(o, 0xb1)));
}
static inline vf v_ldexp(vf a, vf n)
{
	return _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(a), _mm_slli_epi32(_mm_cvtps_epi32(n), 23)));
}
static inline vf v_gather(const float *base, vi idx, vm m)
{
	int32_t i[4];
	float o[4];
	_mm_storeu_si128((__m128i *)i, idx);
	int bits = _mm_movemask_ps(m);
	for (int k = 0; k < 4; k++)
		o[k] = (bits >> k) & 1 ? base[i[k]] : 0.0f;
	return _mm_loadu_ps(o);
}

/* Three-way (de)interleave: p holds VN triples (x y z x y z ...); as in the
 * AVX2 set, two blends and one shuffle per component. */
static inline void v_load3(const float *p, vf *a, vf *b, vf *c)
{
	const vf m0 = _mm_loadu_ps(p), m1 = _mm_loadu_ps(p + 4), m2 = _mm_loadu_ps(p + 8);
	const vf ta = _mm_blend_ps(_mm_blend_ps(m0, m1, 0x4), m2, 0x2); /* a0 a3 a2 a1 */
	const vf tb = _mm_blend_ps(_mm_blend_ps(m0, m1, 0x9), m2, 0x4); /* b1 b0 b3 b2 */
	const vf tc = _mm_blend_ps(_mm_blend_ps(m0, m1, 0x2), m2, 0x9); /* c2 c1 c0 c3 */
	*a = _mm_shuffle_ps(ta, ta, _MM_SHUFFLE(1, 2, 3, 0));
	*b = _mm_shuffle_ps(tb, tb, _MM_SHUFFLE(2, 3, 0, 1));
	*c = _mm_shuffle_ps(tc, tc, _MM_SHUFFLE(3, 0, 1, 2));
}
static inline void v_store3(float *p, vf a, vf b, vf c)
{
	a = _mm_shuffle_ps(a, a, _MM_SHUFFLE(1, 2, 3, 0)); /* a0 a3 a2 a1 */
	b = _mm_shuffle_ps(b, b, _MM_SHUFFLE(2, 3, 0, 1)); /* b1 b0 b3 b2 */
	c = _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 0, 1, 2)); /* c2 c1 c0 c3 */
	_mm_storeu_ps(p, _mm_blend_ps(_mm_blend_ps(a, b, 0x2), c, 0x4));
	_mm_storeu_ps(p + 4, _mm_blend_ps(_mm_blend_ps(a, b, 0x9), c, 0x2));
	_mm_storeu_ps(p + 8, _mm_blend_ps(_mm_blend_ps(a, b, 0x4), c, 0x9));
}
/* VN bytes (0 .. 255) as float lanes */
static inline vf v_load_u8(const uint8_t *p)
{
	int32_t v;
	memcpy(&v, p, sizeof v);
	return _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(v)));
}
/* VN bytes from lanes holding 0 .. 255 */
static inline void vi_store_u8(uint8_t *p, vi a)
{
	const __m128i w = _mm_packus_epi32(a, a);
	const int32_t v = _mm_cvtsi128_si32(_mm_packus_epi16(w, w));
	memcpy(p, &v, sizeof v);
}

/* Four-way deinterleave: v[0..3] hold 4 VN consecutive values p; q[k] gets
 * p[k], p[k + 4], p[k + 8], p[k + 12] (a 4 x 4 transpose). */
static inline void v_deinterleave4(const vf v[4], vf q[4])
{
	const vf t0 = _mm_unpacklo_ps(v[0], v[1]), t1 = _mm_unpackhi_ps(v[0], v[1]);
	const vf t2 = _mm_unpacklo_ps(v[2], v[3]), t3 = _mm_unpackhi_ps(v[2], v[3]);
	q[0] = _mm_movelh_ps(t0, t2);
	q[1] = _mm_movehl_ps(t2, t0);
	q[2] = _mm_movelh_ps(t1, t3);
	q[3] = _mm_movehl_ps(t3, t1);
}

/* Four-way interleave, v_deinterleave4's inverse (the same 4 x 4 transpose). */
static inline void v_interleave4(const vf v[4], vf q[4])
{
	v_deinterleave4(v, q);
}

/* VN x VN transpose in registers: lane j of r[i] <-> lane i of r[j] */
static inline void v_transpose(vf r[4])
{
	_MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
}

/* the largest lane */
static inline float v_hmax(vf a)
{
	__m128 m = _mm_max_ps(a, _mm_movehl_ps(a, a));
	return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}

#endif
