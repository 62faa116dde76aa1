/* SPDX-License-Identifier: MIT */
/* The AO history's reprojection built for avx2 (flags: src/meson.build). */
#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "motion/ao_reproject_simd.inc.c"
