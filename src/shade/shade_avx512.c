/* SPDX-License-Identifier: MIT */
/*
 * The shaded image built for AVX-512 at 16 lanes (simd/simd_avx512.h;
 * compiler flags in src/meson.build).
 */
#include <math.h>

#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "shade/shade_simd.inc.c"
