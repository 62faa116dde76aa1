/* SPDX-License-Identifier: MIT */
/* The motion estimate's pair kernel built for generic (compiler flags set in src/meson.build). */
#include "simd/simd_generic.h"
#define DAO_ISA_FN(name) name##_generic
#include "motion/icp_pairs_simd.inc.c"
