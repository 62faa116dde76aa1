/* SPDX-License-Identifier: MIT */
/* Exposes this ISA's fastmath functions to the tests (tests/simd). */
#include "simd/fastmath.h"
#include "simd/fastmath_check.h"

void DAO_ISA_FN(dao_fastmath_eval)(enum dao_fastmath_fn fn, const float *in, float *out, int n)
{
	for (int i = 0; i + VN <= n; i += VN) {
		vf x = v_load(in + i), a, b;
		switch (fn) {
		case DAO_FM_ACOS:
			v_store(out + i, v_acos(x));
			break;
		case DAO_FM_ACOS_FAST:
			v_store(out + i, v_acos_fast(x));
			break;
		case DAO_FM_SIN:
			v_sincos(x, &a, &b);
			v_store(out + i, a);
			break;
		case DAO_FM_COS:
			v_sincos(x, &a, &b);
			v_store(out + i, b);
			break;
		case DAO_FM_EXP:
			v_store(out + i, v_exp_neg(x));
			break;
		case DAO_FM_EXP2_FAST:
			v_store(out + i, v_exp2_neg_fast(x));
			break;
		case DAO_FM_RCP:
			v_store(out + i, v_rcp(x));
			break;
		case DAO_FM_RSQRT:
			v_store(out + i, v_rsqrt(x));
			break;
		}
	}
}
