/* SPDX-License-Identifier: MIT */
/* The AO history's reprojection built for generic (flags: src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "motion/ao_reproject_simd.inc.c"
