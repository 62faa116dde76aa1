/* SPDX-License-Identifier: MIT */
/* Plane denoise built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "denoise/denoise_plane_simd.inc.c"
