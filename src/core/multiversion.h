/* SPDX-License-Identifier: MIT */
/*
 * DAO_MULTIVERSION before a function with simple loops (decode, conversions,
 * plane copies) has the compiler build it for the x86-64-v4 (AVX-512),
 * x86-64-v3 (AVX2) and baseline levels and pick one by the CPU when the
 * library loads (GCC target_clones, an ifunc).  For loops whose result does
 * not depend on the instruction set (no approximations), so unlike the kernel
 * sets of pipeline/kernels.c they need no oracle test of their own.
 * Elsewhere it expands to nothing.
 */
#ifndef DAO_CORE_MULTIVERSION_H
#define DAO_CORE_MULTIVERSION_H

/* GCC only: Clang (14) emits the dispatcher only where every declaration
 * carries the attribute, so calls from other files do not link */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
	defined(__gnu_linux__) && !defined(DAO_NO_MULTIVERSION)
#define DAO_MULTIVERSION \
	__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define DAO_MULTIVERSION
#endif

#endif
