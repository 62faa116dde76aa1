/* SPDX-License-Identifier: MIT */
/* Domain-transform depth filter built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "depth/domain_simd.inc.c"
