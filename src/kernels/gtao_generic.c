/* SPDX-License-Identifier: MIT */
/* GTAO kernel built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "kernels/gtao_simd.inc.c"
