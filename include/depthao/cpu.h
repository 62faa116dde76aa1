/* SPDX-License-Identifier: MIT */
/* What the CPU offers and which kernel builds can run on it. */
#ifndef DEPTHAO_CPU_H
#define DEPTHAO_CPU_H

#include <stddef.h>

#include <depthao/api.h>
#include <depthao/params.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Name of a kernel set as the "simd" parameter spells it ("avx2", "reference", ...). */
DAO_API const char *dao_simd_name(enum dao_simd simd);

/* 1 if this build has the kernel set and this CPU can run it (AUTO and REFERENCE: always). */
DAO_API int dao_simd_supported(enum dao_simd simd);

/* The kernel set AUTO resolves to on this CPU. */
DAO_API enum dao_simd dao_simd_best(void);

/* CPUs this process may run on (at least 1): what threads = 0 uses. */
DAO_API int dao_cpu_count(void);

/* The CPU's model name (e.g. "AMD EPYC 7B13"), or "unknown"; always NUL-terminated. */
DAO_API void dao_cpu_model(char *buf, size_t len);

#ifdef __cplusplus
}
#endif

#endif
