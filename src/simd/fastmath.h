/* SPDX-License-Identifier: MIT */
/*
 * Vector acos / sin / cos over the SIMD vocabulary; include after one of
 * simd_avx2.h, simd_sse41.h or simd_generic.h.  Errors against libm are
 * measured by tests/simd/test_fastmath.c (bounds in that file).
 */
#ifndef DAO_SIMD_FASTMATH_H
#define DAO_SIMD_FASTMATH_H

/*
 * acos(x), x in [-1, 1]: Abramowitz & Stegun 4.4.46,
 * acos(x) = sqrt(1 - x) (a0 + a1 x + ... + a7 x^7) for 0 <= x <= 1 with
 * absolute error <= 2e-8, and acos(-x) = pi - acos(x).
 */
static inline vf v_acos(vf x)
{
	vf ax = v_min(v_abs(x), v_set1(1.0f));
	vf p = v_set1(-0.0012624911f);
	p = v_fma(p, ax, v_set1(0.0066700901f));
	p = v_fma(p, ax, v_set1(-0.0170881256f));
	p = v_fma(p, ax, v_set1(0.0308918810f));
	p = v_fma(p, ax, v_set1(-0.0501743046f));
	p = v_fma(p, ax, v_set1(0.0889789874f));
	p = v_fma(p, ax, v_set1(-0.2145988016f));
	p = v_fma(p, ax, v_set1(1.5707963050f));
	vf r = v_mul(v_sqrt(v_sub(v_set1(1.0f), ax)), p);
	return v_sel(v_lt(x, v_zero()), v_sub(v_set1(3.14159265358979f), r), r);
}

/*
 * acos(x), x in [-1, 1]: Abramowitz & Stegun 4.4.45,
 * sqrt(1 - x) (a0 + a1 x + a2 x^2 + a3 x^3) for 0 <= x <= 1 (6.8e-5
 * absolute), and acos(-x) = pi - acos(x), with the square root from the
 * hardware estimate of 1/sqrt: 4.2e-4 absolute with a 12-bit estimate (SSE,
 * AVX2).  Half the polynomial of v_acos and no square root, for the GTAO
 * tile kernel's horizon and normal angles (its oracle bound in tests/simd).
 */
/* sqrt(a) for a >= 0 from the hardware estimate of 1/sqrt: a / sqrt(a), 0 at 0 */
static inline vf v_sqrt_fast(vf a)
{
	return v_sel(v_gt(a, v_zero()), v_mul(a, v_rsqrt_fast(a)), v_zero());
}

/* v_acos_fast of |x| = ax <= 1 (x's sign decides the reflection) */
static inline vf v_acos_fast_abs(vf x, vf ax)
{
	vf p = v_set1(-0.0187293f);
	p = v_fma(p, ax, v_set1(0.0742610f));
	p = v_fma(p, ax, v_set1(-0.2121144f));
	p = v_fma(p, ax, v_set1(1.5707288f));
	vf r = v_mul(v_sqrt_fast(v_sub(v_set1(1.0f), ax)), p);
	return v_sel(v_lt(x, v_zero()), v_sub(v_set1(3.14159265358979f), r), r);
}

static inline vf v_acos_fast(vf x)
{
	return v_acos_fast_abs(x, v_min(v_abs(x), v_set1(1.0f)));
}

/* v_acos_fast(x) for x already in [-1, 1]: the same, without the clamp */
static inline vf v_acos_fast_unit(vf x)
{
	return v_acos_fast_abs(x, v_abs(x));
}

/*
 * sin and cos of x, |x| <= ~1e4: quadrant reduction r = x - k pi/2 with pi/2
 * split in two parts (Cody & Waite), then Taylor series on |r| <= pi/4
 * (truncation below 2e-9).
 */
static inline void v_sincos(vf x, vf *s, vf *c)
{
	vf k = v_round(v_mul(x, v_set1(0.636619772367581f)));
	vf r = v_fma(k, v_set1(-1.57079637050628662f), x);
	r = v_fma(k, v_set1(4.37113900018624283e-8f), r);
	vf r2 = v_mul(r, r);
	vf ps = v_set1(2.7557319e-6f);                 /* 1/9! */
	ps = v_fma(ps, r2, v_set1(-1.98412698e-4f));   /* -1/7! */
	ps = v_fma(ps, r2, v_set1(8.33333333e-3f));    /* 1/5! */
	ps = v_fma(ps, r2, v_set1(-1.66666667e-1f));   /* -1/3! */
	vf sr = v_fma(v_mul(ps, r2), r, r);
	vf pc = v_set1(-2.7557319e-7f);                /* -1/10! */
	pc = v_fma(pc, r2, v_set1(2.48015873e-5f));    /* 1/8! */
	pc = v_fma(pc, r2, v_set1(-1.38888889e-3f));   /* -1/6! */
	pc = v_fma(pc, r2, v_set1(4.16666667e-2f));    /* 1/4! */
	pc = v_fma(pc, r2, v_set1(-0.5f));
	vf cr = v_fma(pc, r2, v_set1(1.0f));
	/* quadrant q = k mod 4 */
	vf q = v_sub(k, v_mul(v_set1(4.0f), v_floor(v_mul(k, v_set1(0.25f)))));
	vm odd = m_or(v_eq(q, v_set1(1.0f)), v_eq(q, v_set1(3.0f)));
	vf ss = v_sel(odd, cr, sr), cc = v_sel(odd, sr, cr);
	*s = v_sel(v_ge(q, v_set1(2.0f)), v_neg(ss), ss);
	*c = v_sel(m_or(v_eq(q, v_set1(1.0f)), v_eq(q, v_set1(2.0f))), v_neg(cc), cc);
}

/*
 * exp(x) for x <= 0 (0 below -80, where e^x < 2e-35): x = n ln2 + r with |r| <= ln2/2 (ln2 in
 * two parts), e^r by a degree-5 polynomial fitted for least maximum relative
 * error on that interval (1.4e-7 with float coefficients), then scaled by 2^n.
 */
static inline vf v_exp_neg(vf x)
{
	vm under = v_lt(x, v_set1(-80.0f));
	x = v_max(x, v_set1(-80.0f));
	vf n = v_round(v_mul(x, v_set1(1.44269504088896f)));
	vf r = v_fma(n, v_set1(-0.693145751953125f), x);
	r = v_fma(n, v_set1(-1.428606820309417e-6f), r);
	vf p = v_set1(8.297644556e-03f);
	p = v_fma(p, r, v_set1(4.191537946e-02f));
	p = v_fma(p, r, v_set1(1.666757464e-01f));
	p = v_fma(p, r, v_set1(4.999889433e-01f));
	p = v_fma(p, r, v_set1(9.999997020e-01f));
	p = v_fma(p, r, v_set1(1.000000119e+00f));
	return v_sel(under, v_zero(), v_ldexp(p, n));
}

/*
 * 2^x for x <= 0 to 7.5e-5 relative, for weights (callers fold log2 e into
 * their constants): x = n + r with n = round(x), |r| <= 1/2, and 2^r from the
 * degree-3 polynomial of least maximum relative error for e^y on |y| <=
 * ln 2 / 2, rescaled (coefficient k times ln 2^k); no exact 0 below -115
 * (2^-115 = 2.4e-35 there, as good as 0 for a weight).
 */
static inline vf v_exp2_neg_fast(vf x)
{
	x = v_max(x, v_set1(-115.0f));
	const vf n = v_round(x), r = v_sub(x, n);
	vf p = v_set1(5.517143733e-02f);
	p = v_fma(p, r, v_set1(2.426108142e-01f));
	p = v_fma(p, r, v_set1(6.932609614e-01f));
	p = v_fma(p, r, v_set1(9.999281168e-01f));
	return v_ldexp(p, n);
}

#endif
