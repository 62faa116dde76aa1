/* SPDX-License-Identifier: MIT */
/* The AO history's reprojection built for avx512 (flags: src/meson.build). */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "motion/ao_reproject_simd.inc.c"
