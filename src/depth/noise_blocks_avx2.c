/* SPDX-License-Identifier: MIT */
/* Noise block statistics built for avx2 (compiler flags set in src/meson.build). */
#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "depth/noise_blocks_simd.inc.c"
