/* SPDX-License-Identifier: MIT */
/* CPU feature detection, the CPU count and the names of the kernel sets. */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <depthao/cpu.h>

#include "simd/cpu_internal.h"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#define DAO_X86 1
#else
#define DAO_X86 0
#endif

const char *const dao_simd_names[DAO_SIMD_COUNT + 1] = {
	[DAO_SIMD_AUTO] = "auto",
	[DAO_SIMD_REFERENCE] = "reference",
	[DAO_SIMD_GENERIC] = "generic",
	[DAO_SIMD_SSE41] = "sse4.1",
	[DAO_SIMD_AVX2] = "avx2",
	[DAO_SIMD_AVX512] = "avx512",
	[DAO_SIMD_COUNT] = NULL,
};

const char *dao_simd_name(enum dao_simd simd)
{
	return (unsigned)simd < DAO_SIMD_COUNT ? dao_simd_names[simd] : "invalid";
}

#if DAO_HAVE_X86_KERNELS
/* F16C from CPUID leaf 1 (ECX bit 29): clang 14's __builtin_cpu_supports does not know
 * "f16c".  Only asked together with avx2, whose check covers the OS saving the YMM state. */
static int cpu_has_f16c(void)
{
	unsigned int a, b, c, d;
	return __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C);
}
#endif

int dao_simd_supported(enum dao_simd simd)
{
	switch (simd) {
	case DAO_SIMD_AUTO:
	case DAO_SIMD_REFERENCE:
	case DAO_SIMD_GENERIC:
		return 1;
#if DAO_HAVE_X86_KERNELS
	/* __builtin_cpu_supports also checks that the OS saves the AVX state */
	case DAO_SIMD_SSE41:
		return __builtin_cpu_supports("sse4.1");
	case DAO_SIMD_AVX2:
		return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
		       cpu_has_f16c();
	case DAO_SIMD_AVX512:
		return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
		       cpu_has_f16c() &&
		       __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
		       __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
#endif
	default:
		return 0;
	}
}

enum dao_simd dao_simd_best(void)
{
	/* measured order on the machines we have (docs/performance.md) */
	static const enum dao_simd order[] = { DAO_SIMD_AVX512, DAO_SIMD_AVX2, DAO_SIMD_SSE41 };
	for (size_t i = 0; i < sizeof order / sizeof order[0]; i++)
		if (dao_simd_supported(order[i]))
			return order[i];
	return DAO_SIMD_GENERIC;
}

enum dao_simd dao_simd_resolve(int simd)
{
	return simd == DAO_SIMD_AUTO ? dao_simd_best() : (enum dao_simd)simd;
}

static void trim(char *s)
{
	size_t a = 0, n = strlen(s);
	while (s[a] == ' ' || s[a] == '\t')
		a++;
	while (n > a && (s[n - 1] == ' ' || s[n - 1] == '\n' || s[n - 1] == '\t' || s[n - 1] == '\0'))
		n--;
	memmove(s, s + a, n - a);
	s[n - a] = '\0';
}

void dao_cpu_model(char *buf, size_t len)
{
	if (!buf || len == 0)
		return;
	snprintf(buf, len, "unknown");
#if DAO_X86
	unsigned int top = __get_cpuid_max(0x80000000u, NULL);
	if (top >= 0x80000004u) {
		unsigned int r[12];
		for (unsigned int i = 0; i < 3; i++)
			__get_cpuid(0x80000002u + i, &r[4 * i], &r[4 * i + 1], &r[4 * i + 2], &r[4 * i + 3]);
		char brand[49];
		memcpy(brand, r, 48);
		brand[48] = '\0';
		trim(brand);
		if (brand[0]) {
			snprintf(buf, len, "%s", brand);
			return;
		}
	}
#endif
	FILE *f = fopen("/proc/cpuinfo", "r");
	if (!f)
		return;
	char line[256];
	while (fgets(line, sizeof line, f)) {
		char *colon = strchr(line, ':');
		if (colon && (strncmp(line, "model name", 10) == 0 || strncmp(line, "Model", 5) == 0)) {
			trim(colon + 1);
			snprintf(buf, len, "%s", colon + 1);
			break;
		}
	}
	fclose(f);
}

int dao_cpu_count(void)
{
	cpu_set_t set;
	if (sched_getaffinity(0, sizeof set, &set) == 0) {
		int n = CPU_COUNT(&set);
		if (n > 0)
			return n;
	}
	long n = sysconf(_SC_NPROCESSORS_ONLN);
	return n > 0 ? (int)n : 1;
}
