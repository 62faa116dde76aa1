/* SPDX-License-Identifier: MIT */
/* Temporal depth filter built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "pipeline/temporal_depth_simd.inc.c"
