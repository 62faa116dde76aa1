/* SPDX-License-Identifier: MIT */
/*
 * SIMD vocabulary for AVX-512 (F, VL, DQ, BW): 16 float lanes; lane masks
 * live in mask registers (compares write them, selects read them), and the
 * hardware estimates of 1/x and 1/sqrt(x) have 14 bits instead of 12.  See
 * simd/README.md.
 */
#ifndef DAO_SIMD_AVX512_H
#define DAO_SIMD_AVX512_H

#include <immintrin.h>
#include <stdint.h>

#define VN 16
#define DAO_SIMD_NAME "avx512"

typedef __m512 vf;
typedef __m512i vi;
typedef __mmask16 vm; /* one bit per lane */

static inline vf v_set1(float a) { return _mm512_set1_ps(a); }
static inline vf v_zero(void) { return _mm512_setzero_ps(); }
static inline vf v_iota(void) { return _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }
static inline vf v_load(const float *p) { return _mm512_loadu_ps(p); }
/* VN IEEE halves (core/half.h) as floats, exact */
static inline vf v_load_h(const uint16_t *p)
{
	return _mm512_cvtph_ps(_mm256_loadu_si256((const __m256i *)p));
}
static inline void v_store(float *p, vf a) { _mm512_storeu_ps(p, a); }
static inline vf v_add(vf a, vf b) { return _mm512_add_ps(a, b); }
static inline vf v_sub(vf a, vf b) { return _mm512_sub_ps(a, b); }
static inline vf v_mul(vf a, vf b) { return _mm512_mul_ps(a, b); }
static inline vf v_div(vf a, vf b) { return _mm512_div_ps(a, b); }
static inline vf v_fma(vf a, vf b, vf c) { return _mm512_fmadd_ps(a, b, c); }
static inline vf v_fnma(vf a, vf b, vf c) { return _mm512_fnmadd_ps(a, b, c); } /* c - a b */
static inline vf v_min(vf a, vf b) { return _mm512_min_ps(a, b); }
static inline vf v_max(vf a, vf b) { return _mm512_max_ps(a, b); }
static inline vf v_sqrt(vf a) { return _mm512_sqrt_ps(a); }
static inline vf v_abs(vf a) { return _mm512_abs_ps(a); }
static inline vf v_neg(vf a) { return _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a), _mm512_set1_epi32((int)0x80000000))); }
static inline vf v_floor(vf a) { return _mm512_roundscale_ps(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
/* nearest, ties to even (as lrintf in the default rounding mode) */
static inline vf v_round(vf a)
{
	return _mm512_roundscale_ps(a, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
}

/* 1/a and 1/sqrt(a): hardware estimate (14 bits) + one Newton step, relative
 * error below 3e-7; for a > 0 (finite) only */
static inline vf v_rcp(vf a)
{
	vf r = _mm512_rcp14_ps(a);
	return _mm512_mul_ps(r, _mm512_fnmadd_ps(a, r, _mm512_set1_ps(2.0f)));
}
/* 1/a, hardware estimate only (relative error < 6.2e-5); 1/0 = inf */
static inline vf v_rcp_fast(vf a) { return _mm512_rcp14_ps(a); }
/* 1/sqrt(a), hardware estimate only (relative error < 6.2e-5) */
static inline vf v_rsqrt_fast(vf a) { return _mm512_rsqrt14_ps(a); }
static inline vf v_rsqrt(vf a)
{
	vf r = _mm512_rsqrt14_ps(a);
	vf ar2 = _mm512_mul_ps(_mm512_mul_ps(a, r), r);
	return _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(0.5f), r),
			     _mm512_sub_ps(_mm512_set1_ps(3.0f), ar2));
}

static inline vm v_lt(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
static inline vm v_le(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
static inline vm v_gt(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
static inline vm v_ge(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ); }
static inline vm v_eq(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
static inline vm m_and(vm a, vm b) { return (vm)(a & b); }
static inline vm m_or(vm a, vm b) { return (vm)(a | b); }
static inline vm m_andnot(vm a, vm b) { return (vm)(a & ~b); } /* a & ~b */
static inline int m_any(vm a) { return a != 0; }
static inline int m_all(vm a) { return a == 0xffff; }
static inline vf v_sel(vm m, vf a, vf b) { return _mm512_mask_blend_ps(m, b, a); }

static inline void vi_store(int32_t *p, vi a) { _mm512_storeu_si512((void *)p, a); }
static inline vi vi_set1(int32_t a) { return _mm512_set1_epi32(a); }
static inline vi vi_add(vi a, vi b) { return _mm512_add_epi32(a, b); }
static inline vi vi_mul(vi a, vi b) { return _mm512_mullo_epi32(a, b); }
/* float lanes holding whole numbers -> int32 */
static inline vi vi_from_whole(vf a) { return _mm512_cvtps_epi32(a); }
/* a rounded to the nearest whole number (ties to even, the default rounding) */
static inline vi vi_from_nearest(vf a) { return _mm512_cvtps_epi32(a); }
/* a where m, else 0 */
static inline vf v_keep(vm m, vf a) { return _mm512_maskz_mov_ps(m, a); }
static inline vi vi_keep(vm m, vi a) { return _mm512_maskz_mov_epi32(m, a); }
/* whether any bit of a is set */
static inline int vi_any(vi a) { return _mm512_test_epi32_mask(a, a) != 0; }
static inline vi vi_sel(vm m, vi a, vi b) { return _mm512_mask_blend_epi32(m, b, a); }
static inline vi vi_or(vi a, vi b) { return _mm512_or_si512(a, b); }
static inline vi vi_andnot(vi a, vi b) { return _mm512_andnot_si512(b, a); } /* a & ~b */
/* the n lowest bits set, n in [0, 32] (a shift by 32 gives 0) */
static inline vi vi_low_bits(vi n)
{
	return _mm512_srlv_epi32(_mm512_set1_epi32(-1), _mm512_sub_epi32(_mm512_set1_epi32(32), n));
}
/* lanes whose bit `bit` (a power of two) is set */
static inline vm m_bit(vi a, int32_t bit) { return _mm512_test_epi32_mask(a, _mm512_set1_epi32(bit)); }
/* lanes with any bit set */
static inline vm m_nonzero(vi a) { return _mm512_test_epi32_mask(a, a); }
/* the OR of all lanes */
static inline uint32_t vi_hor(vi a) { return (uint32_t)_mm512_reduce_or_epi32(a); }
/* a * 2^n for whole n in [-126, 127] (vscalefps) */
static inline vf v_ldexp(vf a, vf n) { return _mm512_scalef_ps(a, n); }
/* base[idx] where m is set, 0 elsewhere (masked lanes are not read) */
static inline vf v_gather(const float *base, vi idx, vm m)
{
	return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), m, idx, base, 4);
}

/*
 * Three-way (de)interleave: p holds VN triples (x y z x y z ...).  Lane i of
 * component k is p[3 i + k]: one two-source permute takes the lanes found in
 * p[0..31], a second one the rest from p[32..47] (store3: the reverse, the
 * second permute adding the third component).
 */
static inline void v_load3(const float *p, vf *a, vf *b, vf *c)
{
	const vf m0 = _mm512_loadu_ps(p), m1 = _mm512_loadu_ps(p + 16), m2 = _mm512_loadu_ps(p + 32);
	const __m512i a1 = _mm512_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21, 24, 27, 30, 0, 0, 0, 0, 0);
	const __m512i a2 = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 20, 23, 26, 29);
	const __m512i b1 = _mm512_setr_epi32(1, 4, 7, 10, 13, 16, 19, 22, 25, 28, 31, 0, 0, 0, 0, 0);
	const __m512i b2 = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 18, 21, 24, 27, 30);
	const __m512i c1 = _mm512_setr_epi32(2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 0, 0, 0, 0, 0, 0);
	const __m512i c2 = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 19, 22, 25, 28, 31);
	*a = _mm512_permutex2var_ps(_mm512_permutex2var_ps(m0, a1, m1), a2, m2);
	*b = _mm512_permutex2var_ps(_mm512_permutex2var_ps(m0, b1, m1), b2, m2);
	*c = _mm512_permutex2var_ps(_mm512_permutex2var_ps(m0, c1, m1), c2, m2);
}
static inline void v_store3(float *p, vf a, vf b, vf c)
{
	const __m512i o01 = _mm512_setr_epi32(0, 16, 0, 1, 17, 0, 2, 18, 0, 3, 19, 0, 4, 20, 0, 5);
	const __m512i o02 = _mm512_setr_epi32(0, 1, 16, 3, 4, 17, 6, 7, 18, 9, 10, 19, 12, 13, 20, 15);
	const __m512i o11 = _mm512_setr_epi32(21, 0, 6, 22, 0, 7, 23, 0, 8, 24, 0, 9, 25, 0, 10, 26);
	const __m512i o12 = _mm512_setr_epi32(0, 21, 2, 3, 22, 5, 6, 23, 8, 9, 24, 11, 12, 25, 14, 15);
	const __m512i o21 = _mm512_setr_epi32(0, 11, 27, 0, 12, 28, 0, 13, 29, 0, 14, 30, 0, 15, 31, 0);
	const __m512i o22 = _mm512_setr_epi32(26, 1, 2, 27, 4, 5, 28, 7, 8, 29, 10, 11, 30, 13, 14, 31);
	_mm512_storeu_ps(p, _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, o01, b), o02, c));
	_mm512_storeu_ps(p + 16, _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, o11, b), o12, c));
	_mm512_storeu_ps(p + 32, _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, o21, b), o22, c));
}
/* VN bytes (0 .. 255) as float lanes */
static inline vf v_load_u8(const uint8_t *p)
{
	return _mm512_cvtepi32_ps(_mm512_cvtepu8_epi32(_mm_loadu_si128((const __m128i *)(const void *)p)));
}
/* VN bytes from lanes holding 0 .. 255 */
static inline void vi_store_u8(uint8_t *p, vi a)
{
	_mm_storeu_si128((__m128i *)(void *)p, _mm512_cvtepi32_epi8(a));
}

/*
 * Four-way deinterleave: v[0..3] hold 4 VN consecutive values p; q[k] gets
 * p[k], p[k + 4], p[k + 8], ... (two rounds of two-source permutes).
 */
static inline void v_deinterleave4(const vf v[4], vf q[4])
{
	const __m512i e01 = _mm512_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28, 1, 5, 9, 13, 17, 21, 25, 29);
	const __m512i e23 = _mm512_setr_epi32(2, 6, 10, 14, 18, 22, 26, 30, 3, 7, 11, 15, 19, 23, 27, 31);
	const __m512i lo = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23);
	const __m512i hi = _mm512_setr_epi32(8, 9, 10, 11, 12, 13, 14, 15, 24, 25, 26, 27, 28, 29, 30, 31);
	const vf u01 = _mm512_permutex2var_ps(v[0], e01, v[1]), u23 = _mm512_permutex2var_ps(v[0], e23, v[1]);
	const vf w01 = _mm512_permutex2var_ps(v[2], e01, v[3]), w23 = _mm512_permutex2var_ps(v[2], e23, v[3]);
	q[0] = _mm512_permutex2var_ps(u01, lo, w01);
	q[1] = _mm512_permutex2var_ps(u01, hi, w01);
	q[2] = _mm512_permutex2var_ps(u23, lo, w23);
	q[3] = _mm512_permutex2var_ps(u23, hi, w23);
}

/*
 * Four-way interleave, v_deinterleave4's inverse: v[k] holds p[k], p[k + 4],
 * ...; q[0..3] get the 4 VN values p in order (pairs of v[0], v[1] and of
 * v[2], v[3] interleaved, then the pairs' pairs: two rounds of permutes).
 */
static inline void v_interleave4(const vf v[4], vf q[4])
{
	const __m512i lo = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
	const __m512i hi = _mm512_setr_epi32(8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31);
	const __m512i p0 = _mm512_setr_epi32(0, 1, 16, 17, 2, 3, 18, 19, 4, 5, 20, 21, 6, 7, 22, 23);
	const __m512i p1 = _mm512_setr_epi32(8, 9, 24, 25, 10, 11, 26, 27, 12, 13, 28, 29, 14, 15, 30, 31);
	const vf xl = _mm512_permutex2var_ps(v[0], lo, v[1]), xh = _mm512_permutex2var_ps(v[0], hi, v[1]);
	const vf yl = _mm512_permutex2var_ps(v[2], lo, v[3]), yh = _mm512_permutex2var_ps(v[2], hi, v[3]);
	q[0] = _mm512_permutex2var_ps(xl, p0, yl);
	q[1] = _mm512_permutex2var_ps(xl, p1, yl);
	q[2] = _mm512_permutex2var_ps(xh, p0, yh);
	q[3] = _mm512_permutex2var_ps(xh, p1, yh);
}

/*
 * VN x VN transpose in registers: lane j of r[i] <-> lane i of r[j].  Pairs
 * of rows interleave by 32 then 64 bits (each 128-bit lane then holds one
 * column of four rows), and two rounds of 128-bit shuffles gather a column's
 * four pieces (64 shuffles).
 */
static inline void v_transpose(vf r[16])
{
	__m512 t[16], u[16];
	for (int i = 0; i < 16; i += 2) {
		t[i] = _mm512_unpacklo_ps(r[i], r[i + 1]);
		t[i + 1] = _mm512_unpackhi_ps(r[i], r[i + 1]);
	}
	for (int g = 0; g < 16; g += 4) {
		const __m512d a = _mm512_castps_pd(t[g]), b = _mm512_castps_pd(t[g + 1]);
		const __m512d c = _mm512_castps_pd(t[g + 2]), d = _mm512_castps_pd(t[g + 3]);
		u[g] = _mm512_castpd_ps(_mm512_unpacklo_pd(a, c));     /* columns 0 4 8 12 */
		u[g + 1] = _mm512_castpd_ps(_mm512_unpackhi_pd(a, c)); /* 1 5 9 13 */
		u[g + 2] = _mm512_castpd_ps(_mm512_unpacklo_pd(b, d)); /* 2 6 10 14 */
		u[g + 3] = _mm512_castpd_ps(_mm512_unpackhi_pd(b, d)); /* 3 7 11 15 */
	}
	for (int k = 0; k < 4; k++) {
		const __m512 v0 = _mm512_shuffle_f32x4(u[k], u[4 + k], 0x44);
		const __m512 v1 = _mm512_shuffle_f32x4(u[k], u[4 + k], 0xee);
		const __m512 v2 = _mm512_shuffle_f32x4(u[8 + k], u[12 + k], 0x44);
		const __m512 v3 = _mm512_shuffle_f32x4(u[8 + k], u[12 + k], 0xee);
		r[k] = _mm512_shuffle_f32x4(v0, v2, 0x88);
		r[4 + k] = _mm512_shuffle_f32x4(v0, v2, 0xdd);
		r[8 + k] = _mm512_shuffle_f32x4(v1, v3, 0x88);
		r[12 + k] = _mm512_shuffle_f32x4(v1, v3, 0xdd);
	}
}

/* the largest lane */
static inline float v_hmax(vf a) { return _mm512_reduce_max_ps(a); }

#endif
