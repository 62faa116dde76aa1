/* SPDX-License-Identifier: MIT */
/* fastmath check entry built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "simd/fastmath_check.inc.c"
