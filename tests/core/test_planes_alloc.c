/* SPDX-License-Identifier: MIT */
/* dao_planes_alloc: large working planes, 2 MiB aligned, on huge pages where offered. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "core/planes_alloc.h"

#define MIB ((size_t)1 << 20)

/* the bracketed word of a /sys/kernel/mm/transparent_hugepage file, or "" */
static void thp_setting(const char *name, char *out, size_t size)
{
	char path[128], line[256];
	snprintf(path, sizeof path, "/sys/kernel/mm/transparent_hugepage/%s", name);
	out[0] = '\0';
	FILE *f = fopen(path, "r");
	if (!f)
		return;
	if (fgets(line, sizeof line, f)) {
		const char *a = strchr(line, '['), *b = a ? strchr(a, ']') : NULL;
		if (a && b && (size_t)(b - a) < size)
			snprintf(out, size, "%.*s", (int)(b - a - 1), a + 1);
	}
	fclose(f);
}

/* kB of huge pages in the mapping that holds p (/proc/self/smaps), or -1 */
static long huge_kb_at(const void *p)
{
	FILE *f = fopen("/proc/self/smaps", "r");
	if (!f)
		return -1;
	char line[512];
	int inside = 0;
	long kb = -1;
	while (fgets(line, sizeof line, f)) {
		unsigned long lo, hi;
		if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' ')) {
			inside = (uintptr_t)p >= lo && (uintptr_t)p < hi;
			continue;
		}
		if (inside && sscanf(line, "AnonHugePages: %ld kB", &kb) == 1)
			break;
	}
	fclose(f);
	return kb;
}

static void test_large_plane(void **state)
{
	(void)state;
	const size_t size = 9 * MIB + 12345; /* not a multiple of the page */
	unsigned char *p = dao_planes_alloc(size);
	assert_non_null(p);
	assert_int_equal((uintptr_t)p % (2 * MIB), 0);
	for (size_t i = 0; i < size; i += 4093)
		assert_int_equal(p[i], 0);
	assert_int_equal(p[size - 1], 0);
	memset(p, 0xa5, size); /* all of it writable */
	char enabled[32], defrag[32];
	thp_setting("enabled", enabled, sizeof enabled);
	thp_setting("defrag", defrag, sizeof defrag);
	const long kb = huge_kb_at(p);
	/* where the kernel offers huge pages on advice and compacts for them
	 * at the fault, the plane is on them */
	if ((!strcmp(enabled, "always") || !strcmp(enabled, "madvise")) &&
	    (!strcmp(defrag, "always") || !strcmp(defrag, "madvise")) && kb >= 0)
		assert_true(kb >= 2048);
	else
		print_message("huge pages not checked: enabled [%s], defrag [%s], %ld kB\n",
			      enabled, defrag, kb);
	dao_planes_free(p, size);
}

static void test_small_and_edge_sizes(void **state)
{
	(void)state;
	assert_null(dao_planes_alloc(0));
	assert_null(dao_planes_alloc(SIZE_MAX));
	assert_null(dao_planes_alloc(SIZE_MAX - MIB));
	dao_planes_free(NULL, 1000);
	unsigned char *p = dao_planes_alloc(1000);
	assert_non_null(p);
	for (int i = 0; i < 1000; i++)
		assert_int_equal(p[i], 0);
	dao_planes_free(p, 1000);
	p = dao_planes_alloc(2 * MIB); /* exactly a huge page */
	assert_non_null(p);
	assert_int_equal((uintptr_t)p % (2 * MIB), 0);
	assert_int_equal(p[2 * MIB - 1], 0);
	memset(p, 1, 2 * MIB);
	dao_planes_free(p, 2 * MIB);
	/* released: the next one of the same size may take its place, and is zero again */
	p = dao_planes_alloc(2 * MIB);
	assert_non_null(p);
	assert_int_equal(p[12345], 0);
	dao_planes_free(p, 2 * MIB);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_large_plane),
		cmocka_unit_test(test_small_and_edge_sizes),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
