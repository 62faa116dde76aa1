/* SPDX-License-Identifier: MIT */
/* Temporal depth filter built for avx512 (compiler flags set in src/meson.build). */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "pipeline/temporal_depth_simd.inc.c"
