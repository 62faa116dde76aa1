/* SPDX-License-Identifier: MIT */
/* Temporal depth filter built for sse41 (compiler flags set in src/meson.build). */
#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "pipeline/temporal_depth_simd.inc.c"
