/* SPDX-License-Identifier: MIT */
/* The reprojection's landing pass built for avx512 (flags: src/meson.build). */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "motion/reproject_land_simd.inc.c"
