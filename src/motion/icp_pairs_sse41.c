/* SPDX-License-Identifier: MIT */
/* The motion estimate's pair kernel built for sse41 (compiler flags set in src/meson.build). */
#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "motion/icp_pairs_simd.inc.c"
