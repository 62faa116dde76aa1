/* SPDX-License-Identifier: MIT */
/* Domain-transform depth filter built for avx2 (compiler flags set in src/meson.build). */
#include "simd/simd_avx2.h"
#define DAO_ISA_FN(name) name##_avx2
#include "depth/domain_simd.inc.c"
