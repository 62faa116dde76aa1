/* SPDX-License-Identifier: MIT */
/* The motion estimate's pair kernel built for avx512 (compiler flags set in src/meson.build). */
#include "simd/simd_avx512.h"
#define DAO_ISA_FN(name) name##_avx512
#include "motion/icp_pairs_simd.inc.c"
