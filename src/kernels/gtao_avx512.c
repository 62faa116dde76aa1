/* SPDX-License-Identifier: MIT */
/*
 * GTAO kernel built for AVX-512 at 16 lanes (simd/simd_avx512.h;
 * compiler flags in src/meson.build).
 */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "kernels/gtao_simd.inc.c"
