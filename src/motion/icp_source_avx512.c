/* SPDX-License-Identifier: MIT */
/* The motion estimate's source grid and target depth built for avx512 (flags: src/meson.build). */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "motion/icp_source_simd.inc.c"
