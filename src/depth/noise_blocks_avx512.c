/* SPDX-License-Identifier: MIT */
/* Noise block statistics built for avx512 (compiler flags set in src/meson.build). */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "depth/noise_blocks_simd.inc.c"
