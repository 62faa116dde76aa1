/* SPDX-License-Identifier: MIT */
/* Depth prefilter built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "depth/prefilter_simd.inc.c"
