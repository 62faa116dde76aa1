/* SPDX-License-Identifier: MIT */
/*
 * SIMD vocabulary in portable GCC/Clang vector extensions: 4 float lanes,
 * lowered to whatever the target has (SSE2 on baseline x86-64, NEON on
 * arm64).  Floor and round use only arithmetic so they vectorise too.
 */
#ifndef DAO_SIMD_GENERIC_H
#define DAO_SIMD_GENERIC_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/half.h"

#define VN 4
#define DAO_SIMD_NAME "generic"

typedef float vf __attribute__((vector_size(16)));
typedef int32_t vi __attribute__((vector_size(16)));
typedef vi vm; /* -1 / 0 lanes, as vector comparisons produce */

static inline vf v_set1(float a) { return (vf){ a, a, a, a }; }
static inline vf v_zero(void) { return (vf){ 0, 0, 0, 0 }; }
static inline vf v_iota(void) { return (vf){ 0, 1, 2, 3 }; }
static inline vf v_load(const float *p) { vf a; memcpy(&a, p, sizeof a); return a; }
/* VN IEEE halves (core/half.h) as floats, exact, lane by lane */
static inline vf v_load_h(const uint16_t *p)
{
	return (vf){ dao_half_to_float(p[0]), dao_half_to_float(p[1]), dao_half_to_float(p[2]),
		     dao_half_to_float(p[3]) };
}
static inline void v_store(float *p, vf a) { memcpy(p, &a, sizeof a); }
static inline vf v_add(vf a, vf b) { return a + b; }
static inline vf v_sub(vf a, vf b) { return a - b; }
static inline vf v_mul(vf a, vf b) { return a * b; }
static inline vf v_div(vf a, vf b) { return a / b; }
static inline vf v_fma(vf a, vf b, vf c) { return a * b + c; }
static inline vf v_fnma(vf a, vf b, vf c) { return c - a * b; } /* c - a b */
static inline vf v_sel(vm m, vf a, vf b) { return (vf)((m & (vi)a) | (~m & (vi)b)); }
static inline vf v_min(vf a, vf b) { return v_sel(a < b, a, b); }
static inline vf v_max(vf a, vf b) { return v_sel(a > b, a, b); }
static inline vf v_sqrt(vf a)
{
	return (vf){ sqrtf(a[0]), sqrtf(a[1]), sqrtf(a[2]), sqrtf(a[3]) };
}
static inline vf v_abs(vf a) { return (vf)((vi)a & (vi){ 0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff }); }
static inline vf v_neg(vf a) { return -a; }
/* valid for |a| < 2^22, far beyond any pixel coordinate */
static inline vf v_round(vf a)
{
	const vf magic = v_set1(12582912.0f); /* 1.5 * 2^23: adding it rounds to an integer, ties to even */
	vf r = (a + magic) - magic;
	return v_sel(v_abs(a) < v_set1(4194304.0f), r, a);
}
static inline vf v_floor(vf a)
{
	vf r = v_round(a);
	return r - v_sel(r > a, v_set1(1.0f), v_zero());
}

/* no estimate instructions to rely on: exact */
static inline vf v_rcp(vf a) { return v_set1(1.0f) / a; }
/* 1/a (exact here; the other sets use a hardware estimate); 1/0 = inf */
static inline vf v_rcp_fast(vf a) { return v_set1(1.0f) / a; }
/* 1/sqrt(a) (exact here; the other sets use a hardware estimate) */
static inline vf v_rsqrt_fast(vf a) { return v_set1(1.0f) / v_sqrt(a); }
static inline vf v_rsqrt(vf a) { return v_set1(1.0f) / v_sqrt(a); }

static inline vm v_lt(vf a, vf b) { return a < b; }
static inline vm v_le(vf a, vf b) { return a <= b; }
static inline vm v_gt(vf a, vf b) { return a > b; }
static inline vm v_ge(vf a, vf b) { return a >= b; }
static inline vm v_eq(vf a, vf b) { return a == b; }
static inline vm m_and(vm a, vm b) { return a & b; }
static inline vm m_or(vm a, vm b) { return a | b; }
static inline vm m_andnot(vm a, vm b) { return a & ~b; }
static inline int m_any(vm a) { return (a[0] | a[1] | a[2] | a[3]) != 0; }
static inline int m_all(vm a) { return (a[0] & a[1] & a[2] & a[3]) != 0; }

static inline void vi_store(int32_t *p, vi a) { memcpy(p, &a, sizeof a); }
static inline vi vi_set1(int32_t a) { return (vi){ a, a, a, a }; }
static inline vi vi_add(vi a, vi b) { return a + b; }
static inline vi vi_mul(vi a, vi b) { return a * b; }
static inline vi vi_from_whole(vf a) { return __builtin_convertvector(a, vi); }
/* a rounded to the nearest whole number (ties to even) */
static inline vi vi_from_nearest(vf a) { return __builtin_convertvector(v_round(a), vi); }
/* a where m, else 0 */
static inline vf v_keep(vm m, vf a) { return (vf)(m & (vi)a); }
static inline vi vi_keep(vm m, vi a) { return m & a; }
/* whether any bit of a is set */
static inline int vi_any(vi a) { return (a[0] | a[1] | a[2] | a[3]) != 0; }
static inline vi vi_sel(vm m, vi a, vi b) { return (m & a) | (~m & b); }
static inline vi vi_or(vi a, vi b) { return a | b; }
static inline vi vi_andnot(vi a, vi b) { return a & ~b; }
/* the n lowest bits set, n in [0, 32] */
static inline vi vi_low_bits(vi n)
{
	/* in unsigned lanes: 1 << 31, and it minus 1, overflow int (UBSan) */
	typedef uint32_t vu __attribute__((vector_size(16)));
	const vu one = { 1, 1, 1, 1 };
	return (vi)((one << (vu)(n & 31)) - one) | (vi)(n > 31);
}
/* lanes whose bit `bit` (a power of two) is set */
static inline vm m_bit(vi a, int32_t bit) { return (a & bit) == bit; }
/* lanes with any bit set */
static inline vm m_nonzero(vi a) { return a != 0; }
/* the OR of all lanes */
static inline uint32_t vi_hor(vi a) { return (uint32_t)(a[0] | a[1] | a[2] | a[3]); }
static inline vf v_ldexp(vf a, vf n)
{
	return (vf)((vi)a + (__builtin_convertvector(n, vi) << 23));
}
static inline vf v_gather(const float *base, vi idx, vm m)
{
	vf o;
	for (int k = 0; k < 4; k++)
		o[k] = m[k] ? base[idx[k]] : 0.0f;
	return o;
}

/* Three-way (de)interleave: p holds VN triples (x y z x y z ...). */
static inline void v_load3(const float *p, vf *a, vf *b, vf *c)
{
	for (int k = 0; k < VN; k++)
		(*a)[k] = p[3 * k], (*b)[k] = p[3 * k + 1], (*c)[k] = p[3 * k + 2];
}
static inline void v_store3(float *p, vf a, vf b, vf c)
{
	for (int k = 0; k < VN; k++)
		p[3 * k] = a[k], p[3 * k + 1] = b[k], p[3 * k + 2] = c[k];
}
/* VN bytes (0 .. 255) as float lanes */
static inline vf v_load_u8(const uint8_t *p)
{
	vf r;
	for (int k = 0; k < VN; k++)
		r[k] = (float)p[k];
	return r;
}
/* VN bytes from lanes holding 0 .. 255 */
static inline void vi_store_u8(uint8_t *p, vi a)
{
	for (int k = 0; k < VN; k++)
		p[k] = (uint8_t)a[k];
}

/* Four-way deinterleave: v[0..3] hold 4 VN consecutive values p; q[k] gets
 * p[k], p[k + 4], p[k + 8], ... */
static inline void v_deinterleave4(const vf v[4], vf q[4])
{
	for (int k = 0; k < 4; k++) {
		float t[VN];
		for (int e = 0; e < VN; e++) {
			const int i = 4 * e + k;
			t[e] = v[i / VN][i % VN];
		}
		memcpy(&q[k], t, sizeof t);
	}
}

/* Four-way interleave, v_deinterleave4's inverse: v[k] holds p[k], p[k + 4],
 * ...; q[0..3] get the 4 VN values p in order. */
static inline void v_interleave4(const vf v[4], vf q[4])
{
	float t[4 * VN];
	for (int i = 0; i < 4 * VN; i++)
		t[i] = v[i % 4][i / 4];
	memcpy(q, t, sizeof t);
}

/* VN x VN transpose: lane j of r[i] <-> lane i of r[j] */
static inline void v_transpose(vf r[4])
{
	float t[4][4];
	for (int i = 0; i < 4; i++)
		memcpy(t[i], &r[i], sizeof t[i]);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			r[i][j] = t[j][i];
}

/* the largest lane */
static inline float v_hmax(vf a)
{
	float m = a[0];
	for (int k = 1; k < VN; k++)
		m = a[k] > m ? a[k] : m;
	return m;
}

#endif
