/* SPDX-License-Identifier: MIT */
/* Noise block statistics built for sse41 (compiler flags set in src/meson.build). */
#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "depth/noise_blocks_simd.inc.c"
