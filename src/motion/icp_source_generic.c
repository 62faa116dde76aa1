/* SPDX-License-Identifier: MIT */
/* The motion estimate's source grid and target depth built for generic (flags: src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "motion/icp_source_simd.inc.c"
