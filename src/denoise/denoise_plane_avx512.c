/* SPDX-License-Identifier: MIT */
/*
 * Plane denoise built for AVX-512 at 16 lanes (simd/simd_avx512.h;
 * compiler flags in src/meson.build).
 */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "denoise/denoise_plane_simd.inc.c"
