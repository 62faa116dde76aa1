/* SPDX-License-Identifier: MIT */
/* The shaded image built for avx2 (compiler flags set in src/meson.build). */
#include <math.h>

#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "shade/shade_simd.inc.c"
