/* SPDX-License-Identifier: MIT */
/* Normals from depth built for avx2 (compiler flags set in src/meson.build). */
#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "normals/normals_simd.inc.c"
