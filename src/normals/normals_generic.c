/* SPDX-License-Identifier: MIT */
/* Normals from depth built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "normals/normals_simd.inc.c"
