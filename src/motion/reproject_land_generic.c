/* SPDX-License-Identifier: MIT */
/* The reprojection's landing pass built for generic (flags: src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "motion/reproject_land_simd.inc.c"
