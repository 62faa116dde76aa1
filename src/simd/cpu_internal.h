/* SPDX-License-Identifier: MIT */
#ifndef DAO_SIMD_CPU_INTERNAL_H
#define DAO_SIMD_CPU_INTERNAL_H

#include <depthao/cpu.h>

/* AUTO -> the best supported set; anything else unchanged. */
enum dao_simd dao_simd_resolve(int simd);

#endif
