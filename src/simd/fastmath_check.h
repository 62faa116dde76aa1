/* SPDX-License-Identifier: MIT */
#ifndef DAO_SIMD_FASTMATH_CHECK_H
#define DAO_SIMD_FASTMATH_CHECK_H

enum dao_fastmath_fn { DAO_FM_ACOS, DAO_FM_ACOS_FAST, DAO_FM_SIN, DAO_FM_COS, DAO_FM_EXP, DAO_FM_EXP2_FAST, DAO_FM_RCP, DAO_FM_RSQRT };

/* out[i] = fn(in[i]) for n a multiple of 16, with one ISA's vector code. */
#define DAO_FASTMATH_PROTO(isa)                                                             \
	void dao_fastmath_eval_##isa(enum dao_fastmath_fn fn, const float *in, float *out, int n)

DAO_FASTMATH_PROTO(generic);
DAO_FASTMATH_PROTO(sse41);
DAO_FASTMATH_PROTO(avx2);
DAO_FASTMATH_PROTO(avx512);

#endif
