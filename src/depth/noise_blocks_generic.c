/* SPDX-License-Identifier: MIT */
/* Noise block statistics built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "depth/noise_blocks_simd.inc.c"
