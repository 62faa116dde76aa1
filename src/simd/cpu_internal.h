/* SPDX-License-Identifier: MIT */
#ifndef DAO_SIMD_CPU_INTERNAL_H
#define DAO_SIMD_CPU_INTERNAL_H

#include <depthao/cpu.h>

/* The names of the kernel sets by enum dao_simd, NULL-terminated: the one table
 * the "simd" parameter (params.c) and dao_simd_name() spell them from. */
extern const char *const dao_simd_names[DAO_SIMD_COUNT + 1];

/* AUTO -> the best supported set; anything else unchanged. */
enum dao_simd dao_simd_resolve(int simd);

#endif
