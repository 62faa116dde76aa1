/* SPDX-License-Identifier: MIT */
/* Domain-transform depth filter built for sse4.1 (compiler flags set in src/meson.build). */
#include "simd/simd_sse41.h"
#define DAO_ISA_FN(name) name##_sse41
#include "depth/domain_simd.inc.c"
