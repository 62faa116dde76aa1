/* SPDX-License-Identifier: MIT */
/*
 * The noise measurement's block statistics (noise_estimate.h) of one block
 * row, per instruction set: included by noise_blocks_<isa>.c after its
 * simd_<isa>.h.  With AVX2 (the avx2 and avx512 sets) eight blocks side by
 * side go in the eight lanes: each row of 8 x 8 pixels is transposed in
 * registers, so that lane j holds block j's pixel, and every lane runs the
 * scalar reference's operations on its block in the reference's order
 * (dao_noise_row_ref, the oracle: the column sums over the rows in double,
 * then over the columns; the links down the columns, then along the rows;
 * med3 as min/max with the reference's operand order, so that even NaN and
 * infinities come out the same).  Bit-identical to the reference by
 * construction (no FMA: C11 mode compiles with -ffp-contract=off) and
 * asserted in tests/depth/test_noise_estimate.c.  Other sets run the
 * reference; so do the last blocks of a row that fill no group of eight.
 */
#include "depth/noise_estimate.h"

#if defined(__AVX2__)
#include <immintrin.h>

#define G 8 /* blocks per group: the lanes */

static inline void transpose8(__m256 *r)
{
	const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
	const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
	const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
	const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
	const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xee);
	const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xee);
	const __m256 u4 = _mm256_shuffle_ps(t4, t6, 0x44), u5 = _mm256_shuffle_ps(t4, t6, 0xee);
	const __m256 u6 = _mm256_shuffle_ps(t5, t7, 0x44), u7 = _mm256_shuffle_ps(t5, t7, 0xee);
	r[0] = _mm256_permute2f128_ps(u0, u4, 0x20), r[1] = _mm256_permute2f128_ps(u1, u5, 0x20);
	r[2] = _mm256_permute2f128_ps(u2, u6, 0x20), r[3] = _mm256_permute2f128_ps(u3, u7, 0x20);
	r[4] = _mm256_permute2f128_ps(u0, u4, 0x31), r[5] = _mm256_permute2f128_ps(u1, u5, 0x31);
	r[6] = _mm256_permute2f128_ps(u2, u6, 0x31), r[7] = _mm256_permute2f128_ps(u3, u7, 0x31);
}

/* the reference's med3: lo = a < b ? a : b, hi = a < b ? b : a, m = hi < c ? hi : c,
 * lo > m ? lo : m (minps(x, y) = x < y ? x : y, maxps(x, y) = x > y ? x : y) */
static inline __m256 med3(__m256 a, __m256 b, __m256 c)
{
	const __m256 lo = _mm256_min_ps(a, b), hi = _mm256_max_ps(b, a);
	return _mm256_max_ps(lo, _mm256_min_ps(hi, c));
}

/* one link: e = d - med3(dm, d, dp) into the squares and the non-zero count */
static inline void link(__m256 dm, __m256 d, __m256 dp, __m256 *e2, __m256i *nz)
{
	const __m256 e = _mm256_sub_ps(d, med3(dm, d, dp));
	*e2 = _mm256_add_ps(*e2, _mm256_mul_ps(e, e));
	/* e != 0 (true for NaN): -1 per lane, subtracted */
	*nz = _mm256_sub_epi32(*nz, _mm256_castps_si256(
					    _mm256_cmp_ps(e, _mm256_setzero_ps(), _CMP_NEQ_UQ)));
}

/* 1/z of the group's 8 x 8 x 8 pixels, transposed (w[r][k]: lane j = block j's
 * pixel (k, r)); the lanes whose 64 values are all > 0 */
static inline __m256 group_w(const float *z, int stride, __m256 w[8][8])
{
	__m256 ok = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
	const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
	for (int r = 0; r < 8; r++) {
		const float *zr = z + (size_t)r * stride;
		for (int j = 0; j < G; j++)
			w[r][j] = _mm256_loadu_ps(zr + DAO_NOISE_BLOCK * j);
		transpose8(w[r]);
		for (int k = 0; k < 8; k++) {
			/* the reference's has / (v + (1 - has)) is 1 / v where v > 0; elsewhere
			 * it is 0 or NaN, here 0: both make the block unusable (w > 0 fails),
			 * and such a value is read by its own block only */
			const __m256 v = w[r][k], has = _mm256_cmp_ps(v, zero, _CMP_GT_OQ);
			const __m256 x = _mm256_and_ps(_mm256_div_ps(one, v), has);
			ok = _mm256_and_ps(ok, _mm256_cmp_ps(x, zero, _CMP_GT_OQ));
			w[r][k] = x;
		}
	}
	return ok;
}

/* the sums of the plane fit, in double, in the reference's order: per
 * column k over the rows, then over the columns (s: s0, su, sv, s2, each
 * two halves of 4 lanes) */
static inline void group_sums(__m256 w[8][8], __m256d s[4][2])
{
	for (int q = 0; q < 4; q++)
		s[q][0] = s[q][1] = _mm256_setzero_pd();
	for (int k = 0; k < 8; k++) {
		const __m256d uk = _mm256_set1_pd(k - 3.5);
		for (int h = 0; h < 2; h++) {
			__m256d c0 = _mm256_setzero_pd(), cv = c0, c2 = c0;
			for (int r = 0; r < 8; r++) {
				const __m128 x = h ? _mm256_extractf128_ps(w[r][k], 1)
						   : _mm256_castps256_ps128(w[r][k]);
				const __m256d c = _mm256_cvtps_pd(x);
				c0 = _mm256_add_pd(c0, c);
				cv = _mm256_add_pd(cv, _mm256_mul_pd(_mm256_set1_pd(r - 3.5), c));
				c2 = _mm256_add_pd(c2, _mm256_mul_pd(c, c));
			}
			s[0][h] = _mm256_add_pd(s[0][h], c0);
			s[1][h] = _mm256_add_pd(s[1][h], _mm256_mul_pd(uk, c0));
			s[2][h] = _mm256_add_pd(s[2][h], cv);
			s[3][h] = _mm256_add_pd(s[3][h], c2);
		}
	}
}

/* the links' squares and non-zero counts, summed over the columns: per
 * column those down it (rows 1 .. 5), then those along the rows (columns 1 .. 5) */
static inline void group_links(__m256 w[8][8], __m256 *se, __m256i *sn)
{
	*se = _mm256_setzero_ps();
	*sn = _mm256_setzero_si256();
	for (int k = 0; k < 8; k++) {
		__m256 e2 = _mm256_setzero_ps(), d[7];
		__m256i nz = _mm256_setzero_si256();
		for (int r = 0; r < 7; r++)
			d[r] = _mm256_sub_ps(w[r + 1][k], w[r][k]);
		for (int r = 1; r <= 5; r++)
			link(d[r - 1], d[r], d[r + 1], &e2, &nz);
		if (k >= 1 && k <= 5)
			for (int r = 0; r < 8; r++) {
				const __m256 dm = _mm256_sub_ps(w[r][k], w[r][k - 1]);
				const __m256 dd = _mm256_sub_ps(w[r][k + 1], w[r][k]);
				const __m256 dp = _mm256_sub_ps(w[r][k + 2], w[r][k + 1]);
				link(dm, dd, dp, &e2, &nz);
			}
		*se = _mm256_add_ps(*se, e2);
		*sn = _mm256_add_epi32(*sn, nz);
	}
}

/* the reference's per-block statistics from the sums */
static inline void group_stats(__m256 ok, __m256d s[4][2], __m256 se, __m256i sn, float *out)
{
	float st[DAO_NOISE_BLOCK_STATS][G];
	for (int h = 0; h < 2; h++) {
		const __m256d s0 = s[0][h], su = s[1][h], sv = s[2][h], s2 = s[3][h];
		const __m256d c64 = _mm256_set1_pd(64.0), c336 = _mm256_set1_pd(336.0);
		__m256d ss = _mm256_sub_pd(s2, _mm256_div_pd(_mm256_mul_pd(s0, s0), c64));
		ss = _mm256_sub_pd(ss, _mm256_div_pd(_mm256_mul_pd(su, su), c336));
		ss = _mm256_sub_pd(ss, _mm256_div_pd(_mm256_mul_pd(sv, sv), c336));
		/* ss > 0 ? ss : 0 (NaN: 0) */
		ss = _mm256_and_pd(ss, _mm256_cmp_pd(ss, _mm256_setzero_pd(), _CMP_GT_OQ));
		const __m256d a = _mm256_sqrt_pd(_mm256_div_pd(ss, _mm256_set1_pd(61.0)));
		_mm_storeu_ps(st[0] + 4 * h, _mm256_cvtpd_ps(a));
		_mm_storeu_ps(st[2] + 4 * h, _mm256_cvtpd_ps(_mm256_div_pd(s0, c64)));
		_mm_storeu_ps(st[3] + 4 * h, _mm256_cvtpd_ps(_mm256_div_pd(su, c336)));
		_mm_storeu_ps(st[4] + 4 * h, _mm256_cvtpd_ps(_mm256_div_pd(sv, c336)));
	}
	const __m256 n = _mm256_cvtepi32_ps(sn), zero = _mm256_setzero_ps();
	const __m256 l = _mm256_div_ps(_mm256_sqrt_ps(_mm256_div_ps(se, n)),
				       _mm256_set1_ps(DAO_NOISE_LINK_IID));
	_mm256_storeu_ps(st[1], _mm256_and_ps(l, _mm256_cmp_ps(n, zero, _CMP_GT_OQ)));
	const int okm = _mm256_movemask_ps(ok);
	for (int j = 0; j < G; j++)
		for (int q = 0; q < DAO_NOISE_BLOCK_STATS; q++)
			out[DAO_NOISE_BLOCK_STATS * j + q] = (okm >> j) & 1 ? st[q][j] : NAN;
}

void DAO_ISA_FN(dao_noise_row)(const float *z, int stride, int nblocks, float *out)
{
	int b = 0;
	for (; b + G <= nblocks; b += G) {
		__m256 w[8][8], se;
		__m256d s[4][2];
		__m256i sn;
		const __m256 ok = group_w(z + (size_t)b * DAO_NOISE_BLOCK, stride, w);
		group_sums(w, s);
		group_links(w, &se, &sn);
		group_stats(ok, s, se, sn, out + DAO_NOISE_BLOCK_STATS * (size_t)b);
	}
	if (b < nblocks)
		dao_noise_row_ref(z + (size_t)b * DAO_NOISE_BLOCK, stride, nblocks - b,
				  out + DAO_NOISE_BLOCK_STATS * (size_t)b);
}
#else
void DAO_ISA_FN(dao_noise_row)(const float *z, int stride, int nblocks, float *out)
{
	dao_noise_row_ref(z, stride, nblocks, out);
}
#endif
