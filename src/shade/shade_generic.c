/* SPDX-License-Identifier: MIT */
/* The shaded image built for generic (compiler flags set in src/meson.build). */
#include <math.h>

#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "shade/shade_simd.inc.c"
