/* SPDX-License-Identifier: MIT */
/*
 * SIMD vocabulary for AVX2 + FMA: 8 float lanes.  Kernels written against
 * this vocabulary (v_*, m_*, vi_*) compile unchanged with simd_sse41.h and
 * simd_generic.h; see simd/README.md.
 */
#ifndef DAO_SIMD_AVX2_H
#define DAO_SIMD_AVX2_H

#include <immintrin.h>
#include <stdint.h>

#define VN 8
#define DAO_SIMD_NAME "avx2"

typedef __m256 vf;
typedef __m256i vi;
typedef __m256 vm; /* all-ones / all-zeros lanes */

static inline vf v_set1(float a) { return _mm256_set1_ps(a); }
static inline vf v_zero(void) { return _mm256_setzero_ps(); }
static inline vf v_iota(void) { return _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7); }
static inline vf v_load(const float *p) { return _mm256_loadu_ps(p); }
/* VN IEEE halves (core/half.h) as floats, exact (F16C: every AVX2 CPU has it) */
static inline vf v_load_h(const uint16_t *p)
{
	return _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)p));
}
static inline void v_store(float *p, vf a) { _mm256_storeu_ps(p, a); }
static inline vf v_add(vf a, vf b) { return _mm256_add_ps(a, b); }
static inline vf v_sub(vf a, vf b) { return _mm256_sub_ps(a, b); }
static inline vf v_mul(vf a, vf b) { return _mm256_mul_ps(a, b); }
static inline vf v_div(vf a, vf b) { return _mm256_div_ps(a, b); }
static inline vf v_fma(vf a, vf b, vf c) { return _mm256_fmadd_ps(a, b, c); }
static inline vf v_fnma(vf a, vf b, vf c) { return _mm256_fnmadd_ps(a, b, c); } /* c - a b */
static inline vf v_min(vf a, vf b) { return _mm256_min_ps(a, b); }
static inline vf v_max(vf a, vf b) { return _mm256_max_ps(a, b); }
static inline vf v_sqrt(vf a) { return _mm256_sqrt_ps(a); }
static inline vf v_abs(vf a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
static inline vf v_neg(vf a) { return _mm256_xor_ps(_mm256_set1_ps(-0.0f), a); }
static inline vf v_floor(vf a) { return _mm256_floor_ps(a); }
/* nearest, ties to even (as lrintf in the default rounding mode) */
static inline vf v_round(vf a)
{
	return _mm256_round_ps(a, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
}

/* 1/a and 1/sqrt(a): hardware estimate (12 bits) + one Newton step, relative
 * error below 3e-7; for a > 0 (finite) only */
static inline vf v_rcp(vf a)
{
	vf r = _mm256_rcp_ps(a);
	return _mm256_mul_ps(r, _mm256_fnmadd_ps(a, r, _mm256_set1_ps(2.0f)));
}
/* 1/a, hardware estimate only (relative error < 3.7e-4); 1/0 = inf */
static inline vf v_rcp_fast(vf a) { return _mm256_rcp_ps(a); }
/* 1/sqrt(a), hardware estimate only (relative error < 3.7e-4) */
static inline vf v_rsqrt_fast(vf a) { return _mm256_rsqrt_ps(a); }
static inline vf v_rsqrt(vf a)
{
	vf r = _mm256_rsqrt_ps(a);
	vf ar2 = _mm256_mul_ps(_mm256_mul_ps(a, r), r);
	return _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(0.5f), r),
			     _mm256_sub_ps(_mm256_set1_ps(3.0f), ar2));
}

static inline vm v_lt(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
static inline vm v_le(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
static inline vm v_gt(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
static inline vm v_ge(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
static inline vm v_eq(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
static inline vm m_and(vm a, vm b) { return _mm256_and_ps(a, b); }
static inline vm m_or(vm a, vm b) { return _mm256_or_ps(a, b); }
static inline vm m_andnot(vm a, vm b) { return _mm256_andnot_ps(b, a); } /* a & ~b */
static inline int m_any(vm a) { return _mm256_movemask_ps(a) != 0; }
static inline int m_all(vm a) { return _mm256_movemask_ps(a) == 0xff; }
/* a where m, else b.  One vblendvps in asm: GCC 12 folds the intrinsic into a
 * select on m < 0, and a mask used by two selects then costs a vpcmpgtd (and
 * a zeroed register) before them, as it cannot tell that m is all-ones or
 * all-zeros lanes. */
static inline vf v_sel(vm m, vf a, vf b)
{
	vf r;
	__asm__("vblendvps %3, %2, %1, %0" : "=x"(r) : "x"(b), "xm"(a), "x"(m));
	return r;
}

static inline void vi_store(int32_t *p, vi a) { _mm256_storeu_si256((__m256i *)(void *)p, a); }
static inline vi vi_set1(int32_t a) { return _mm256_set1_epi32(a); }
static inline vi vi_add(vi a, vi b) { return _mm256_add_epi32(a, b); }
static inline vi vi_mul(vi a, vi b) { return _mm256_mullo_epi32(a, b); }
/* float lanes holding whole numbers -> int32 */
static inline vi vi_from_whole(vf a) { return _mm256_cvtps_epi32(a); }
/* a rounded to the nearest whole number (ties to even, the default rounding) */
static inline vi vi_from_nearest(vf a) { return _mm256_cvtps_epi32(a); }
/* a where m, else 0 (v_sel with 0, as one AND) */
static inline vf v_keep(vm m, vf a) { return _mm256_and_ps(m, a); }
static inline vi vi_keep(vm m, vi a) { return _mm256_and_si256(_mm256_castps_si256(m), a); }
/* whether any bit of a is set */
static inline int vi_any(vi a) { return !_mm256_testz_si256(a, a); }
static inline vi vi_sel(vm m, vi a, vi b)
{
	return _mm256_castps_si256(
		_mm256_blendv_ps(_mm256_castsi256_ps(b), _mm256_castsi256_ps(a), m));
}
static inline vi vi_or(vi a, vi b) { return _mm256_or_si256(a, b); }
static inline vi vi_andnot(vi a, vi b) { return _mm256_andnot_si256(b, a); } /* a & ~b */
/* the n lowest bits set, n in [0, 32] (a shift by 32 gives 0) */
static inline vi vi_low_bits(vi n)
{
	return _mm256_srlv_epi32(_mm256_set1_epi32(-1), _mm256_sub_epi32(_mm256_set1_epi32(32), n));
}
/* lanes whose bit `bit` (a power of two) is set */
static inline vm m_bit(vi a, int32_t bit)
{
	const __m256i b = _mm256_set1_epi32(bit);
	return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(a, b), b));
}
/* lanes with any bit set */
static inline vm m_nonzero(vi a)
{
	return _mm256_castsi256_ps(_mm256_xor_si256(_mm256_cmpeq_epi32(a, _mm256_setzero_si256()),
						    _mm256_set1_epi32(-1)));
}
/* the OR of all lanes */
static inline uint32_t vi_hor(vi a)
{
	__m128i o = _mm_or_si128(_mm256_castsi256_si128(a), _mm256_extracti128_si256(a, 1));
	o = _mm_or_si128(o, _mm_shuffle_epi32(o, 0x4e));
	return (uint32_t)_mm_cvtsi128_si32(_mm_or_si128(o, _mm_shuffle_epi32(o, 0xb1)));
}
/* a * 2^n for whole n in [-126, 127] (adds n to the exponent field) */
static inline vf v_ldexp(vf a, vf n)
{
	return _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(a),
						    _mm256_slli_epi32(_mm256_cvtps_epi32(n), 23)));
}
/* base[idx] where m is set, 0 elsewhere (masked lanes are not read) */
static inline vf v_gather(const float *base, vi idx, vm m)
{
	return _mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, idx, m, 4);
}

/*
 * Three-way (de)interleave: p holds VN triples (x y z x y z ...).  The 8
 * elements of one component sit at distinct positions mod 8 of the three
 * input vectors, so two blends gather them into one vector and one permute
 * puts them in order (store3: the reverse).
 */
static inline void v_load3(const float *p, vf *a, vf *b, vf *c)
{
	const vf m0 = _mm256_loadu_ps(p), m1 = _mm256_loadu_ps(p + 8), m2 = _mm256_loadu_ps(p + 16);
	*a = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(m0, m1, 0x92), m2, 0x24),
				      _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
	*b = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(m0, m1, 0x24), m2, 0x49),
				      _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
	*c = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(m0, m1, 0x49), m2, 0x92),
				      _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}
static inline void v_store3(float *p, vf a, vf b, vf c)
{
	a = _mm256_permutevar8x32_ps(a, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
	b = _mm256_permutevar8x32_ps(b, _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
	c = _mm256_permutevar8x32_ps(c, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
	_mm256_storeu_ps(p, _mm256_blend_ps(_mm256_blend_ps(a, b, 0x92), c, 0x24));
	_mm256_storeu_ps(p + 8, _mm256_blend_ps(_mm256_blend_ps(a, b, 0x24), c, 0x49));
	_mm256_storeu_ps(p + 16, _mm256_blend_ps(_mm256_blend_ps(a, b, 0x49), c, 0x92));
}
/* VN bytes (0 .. 255) as float lanes */
static inline vf v_load_u8(const uint8_t *p)
{
	return _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)(const void *)p)));
}
/* VN bytes from lanes holding 0 .. 255 */
static inline void vi_store_u8(uint8_t *p, vi a)
{
	const __m128i w = _mm_packus_epi32(_mm256_castsi256_si128(a), _mm256_extracti128_si256(a, 1));
	_mm_storel_epi64((__m128i *)(void *)p, _mm_packus_epi16(w, w));
}

/*
 * Four-way deinterleave: v[0..3] hold 4 VN consecutive values p; q[k] gets
 * p[k], p[k + 4], p[k + 8], ...  A 4 x 4 transpose within each 128-bit half
 * leaves q[k] as p[k], p[k + 8], p[k + 16], p[k + 24] | p[k + 4], ...; one
 * permute restores the order.
 */
static inline void v_deinterleave4(const vf v[4], vf q[4])
{
	const vf t0 = _mm256_unpacklo_ps(v[0], v[1]), t1 = _mm256_unpackhi_ps(v[0], v[1]);
	const vf t2 = _mm256_unpacklo_ps(v[2], v[3]), t3 = _mm256_unpackhi_ps(v[2], v[3]);
	const __m256i ord = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
	q[0] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)), ord);
	q[1] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)), ord);
	q[2] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)), ord);
	q[3] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2)), ord);
}

/*
 * Four-way interleave, v_deinterleave4's inverse: v[k] holds p[k], p[k + 4],
 * ...; q[0..3] get the 4 VN values p in order.  A 4 x 4 transpose per 128-bit
 * half gives p[0..3] | p[16..19] and so on; swapping halves restores the order.
 */
static inline void v_interleave4(const vf v[4], vf q[4])
{
	const vf t0 = _mm256_unpacklo_ps(v[0], v[1]), t1 = _mm256_unpackhi_ps(v[0], v[1]);
	const vf t2 = _mm256_unpacklo_ps(v[2], v[3]), t3 = _mm256_unpackhi_ps(v[2], v[3]);
	const vf a = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
	const vf b = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
	const vf c = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
	const vf d = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
	q[0] = _mm256_permute2f128_ps(a, b, 0x20);
	q[1] = _mm256_permute2f128_ps(c, d, 0x20);
	q[2] = _mm256_permute2f128_ps(a, b, 0x31);
	q[3] = _mm256_permute2f128_ps(c, d, 0x31);
}

/*
 * VN x VN transpose in registers: lane j of r[i] <-> lane i of r[j]
 * (unpack by 32 bits, shuffle by 64, then swap 128-bit halves: 24 shuffles).
 */
static inline void v_transpose(vf r[8])
{
	__m256 t[8], s[8];
	for (int i = 0; i < 8; i += 2) {
		t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]);
		t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);
	}
	for (int g = 0; g < 8; g += 4) {
		s[g] = _mm256_shuffle_ps(t[g], t[g + 2], _MM_SHUFFLE(1, 0, 1, 0));     /* columns 0 4 */
		s[g + 1] = _mm256_shuffle_ps(t[g], t[g + 2], _MM_SHUFFLE(3, 2, 3, 2)); /* 1 5 */
		s[g + 2] = _mm256_shuffle_ps(t[g + 1], t[g + 3], _MM_SHUFFLE(1, 0, 1, 0)); /* 2 6 */
		s[g + 3] = _mm256_shuffle_ps(t[g + 1], t[g + 3], _MM_SHUFFLE(3, 2, 3, 2)); /* 3 7 */
	}
	for (int k = 0; k < 4; k++) {
		r[k] = _mm256_permute2f128_ps(s[k], s[4 + k], 0x20);
		r[4 + k] = _mm256_permute2f128_ps(s[k], s[4 + k], 0x31);
	}
}

/* the largest lane */
static inline float v_hmax(vf a)
{
	__m128 m = _mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
	m = _mm_max_ps(m, _mm_movehl_ps(m, m));
	return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}

#endif
