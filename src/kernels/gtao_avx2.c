/* SPDX-License-Identifier: MIT */
/* GTAO kernel built for avx2 (compiler flags set in src/meson.build). */
#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "kernels/gtao_simd.inc.c"
