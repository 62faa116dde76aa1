/* SPDX-License-Identifier: MIT */
/*
 * IEEE half precision (binary16) in software: float to half rounded to
 * nearest even, as the F16C instruction VCVTPS2PH with its default rounding
 * (NaNs become the quiet NaN 0x7e00), and half to float, exact.  For planes
 * that the AVX2 and AVX-512 kernels read with VCVTPH2PS and the others, and
 * the references, convert lane by lane (F. Giesen's branch-light method).
 */
#ifndef DAO_CORE_HALF_H
#define DAO_CORE_HALF_H

#include <stdint.h>
#include <string.h>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

static inline uint16_t dao_half_from_float(float x)
{
	uint32_t f;
	memcpy(&f, &x, sizeof f);
	const uint32_t sign = f & 0x80000000u;
	f ^= sign;
	uint32_t o;
	if (f >= (uint32_t)(127 + 16) << 23) { /* 2^16 and up, inf, NaN */
		o = f > 0x7f800000u ? 0x7e00u : 0x7c00u;
	} else if (f < (uint32_t)113 << 23) { /* below 2^-14: a subnormal half or 0 */
		const uint32_t magic_u = (uint32_t)((127 - 15) + (23 - 10) + 1) << 23;
		float m, v;
		memcpy(&m, &magic_u, sizeof m);
		memcpy(&v, &f, sizeof v);
		v += m; /* the add rounds to nearest even at the half's last bit */
		memcpy(&o, &v, sizeof o);
		o -= magic_u;
	} else {
		const uint32_t odd = (f >> 13) & 1u;
		f += ((uint32_t)(15 - 127) << 23) + 0xfffu + odd;
		o = f >> 13; /* a carry out of 65504 makes it inf */
	}
	return (uint16_t)(o | (sign >> 16));
}

static inline float dao_half_to_float(uint16_t h)
{
	const uint32_t shifted_exp = (uint32_t)0x7c00 << 13;
	uint32_t o = ((uint32_t)h & 0x7fffu) << 13;
	const uint32_t e = o & shifted_exp;
	o += (uint32_t)(127 - 15) << 23;
	float r;
	if (e == shifted_exp) { /* inf, NaN */
		o += (uint32_t)(128 - 16) << 23;
	} else if (e == 0) { /* 0, subnormal */
		const uint32_t magic_u = (uint32_t)113 << 23;
		float m;
		memcpy(&m, &magic_u, sizeof m);
		o += 1u << 23;
		memcpy(&r, &o, sizeof r);
		r -= m;
		memcpy(&o, &r, sizeof o);
	}
	o |= ((uint32_t)h & 0x8000u) << 16;
	memcpy(&r, &o, sizeof r);
	return r;
}

/* x rounded to the nearest half (what a half plane gives back). */
static inline float dao_half_round(float x)
{
	return dao_half_to_float(dao_half_from_float(x));
}

#ifdef __SSE2__
/* dao_half_from_float of 4 lanes, in the low 64 bits. */
static inline __m128i dao_half_from_ps_sse2(__m128 x)
{
	const __m128i fi = _mm_castps_si128(x);
	const __m128i sign = _mm_and_si128(fi, _mm_set1_epi32((int)0x80000000u));
	const __m128i f = _mm_xor_si128(fi, sign);
	const __m128i big = _mm_cmpgt_epi32(f, _mm_set1_epi32(((127 + 16) << 23) - 1));
	const __m128i nan = _mm_cmpgt_epi32(f, _mm_set1_epi32(0x7f800000));
	const __m128i infnan =
		_mm_or_si128(_mm_set1_epi32(0x7c00), _mm_and_si128(nan, _mm_set1_epi32(0x0200)));
	const __m128i sub = _mm_cmplt_epi32(f, _mm_set1_epi32(113 << 23));
	const __m128i magic = _mm_set1_epi32(((127 - 15) + (23 - 10) + 1) << 23);
	const __m128i vs = _mm_sub_epi32(
		_mm_castps_si128(_mm_add_ps(_mm_castsi128_ps(f), _mm_castsi128_ps(magic))), magic);
	const __m128i odd = _mm_and_si128(_mm_srli_epi32(f, 13), _mm_set1_epi32(1));
	const __m128i vn = _mm_srli_epi32(
		_mm_add_epi32(_mm_add_epi32(f, _mm_set1_epi32((int)(((uint32_t)(15 - 127) << 23) + 0xfffu))),
			      odd),
		13);
	__m128i o = _mm_or_si128(_mm_and_si128(sub, vs), _mm_andnot_si128(sub, vn));
	o = _mm_or_si128(_mm_and_si128(big, infnan), _mm_andnot_si128(big, o));
	o = _mm_or_si128(o, _mm_srli_epi32(sign, 16));
	/* sign-extended from 16 bits, so that the saturating pack keeps the bits */
	o = _mm_srai_epi32(_mm_slli_epi32(o, 16), 16);
	return _mm_packs_epi32(o, o);
}
#endif

#endif
