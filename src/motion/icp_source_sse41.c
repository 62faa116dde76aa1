/* SPDX-License-Identifier: MIT */
/* The motion estimate's source grid and target depth built for sse41 (flags: src/meson.build). */
#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "motion/icp_source_simd.inc.c"
