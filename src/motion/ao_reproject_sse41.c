/* SPDX-License-Identifier: MIT */
/* The AO history's reprojection built for sse41 (flags: src/meson.build). */
#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "motion/ao_reproject_simd.inc.c"
