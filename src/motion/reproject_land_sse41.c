/* SPDX-License-Identifier: MIT */
/* The reprojection's landing pass built for sse41 (flags: src/meson.build). */
#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "motion/reproject_land_simd.inc.c"
