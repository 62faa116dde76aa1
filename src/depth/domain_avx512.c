/* SPDX-License-Identifier: MIT */
/*
 * Domain-transform depth filter built for AVX-512 at 16 lanes
 * (simd/simd_avx512.h; compiler flags in src/meson.build).
 */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "depth/domain_simd.inc.c"
