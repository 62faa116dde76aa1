/* SPDX-License-Identifier: MIT */
/* The motion estimate's source grid and target depth built for avx2 (flags: src/meson.build). */
#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "motion/icp_source_simd.inc.c"
