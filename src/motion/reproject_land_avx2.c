/* SPDX-License-Identifier: MIT */
/* The reprojection's landing pass built for avx2 (flags: src/meson.build). */
#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "motion/reproject_land_simd.inc.c"
