/* SPDX-License-Identifier: MIT */
/* The shaded image built for sse41 (compiler flags set in src/meson.build). */
#include <math.h>

#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "shade/shade_simd.inc.c"
