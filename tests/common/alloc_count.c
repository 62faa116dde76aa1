/* SPDX-License-Identifier: MIT */
/* The allocation counter of alloc_count.h: glibc's allocator interposed. */
#define _GNU_SOURCE
#include <errno.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>

#include "common/alloc_count.h"

#ifdef __GLIBC__
void *__libc_malloc(size_t n);
void *__libc_calloc(size_t n, size_t m);
void *__libc_realloc(void *p, size_t n);
void *__libc_memalign(size_t a, size_t n);
void __libc_free(void *p);

static atomic_int counting;
static atomic_long allocations;

static void count(void)
{
	if (atomic_load(&counting))
		atomic_fetch_add(&allocations, 1);
}

void *malloc(size_t n)
{
	count();
	return __libc_malloc(n);
}

void *calloc(size_t n, size_t m)
{
	count();
	return __libc_calloc(n, m);
}

void *realloc(void *p, size_t n)
{
	count();
	return __libc_realloc(p, n);
}

void *aligned_alloc(size_t a, size_t n)
{
	count();
	return __libc_memalign(a, n);
}

int posix_memalign(void **out, size_t a, size_t n)
{
	count();
	*out = __libc_memalign(a, n);
	return *out ? 0 : ENOMEM;
}

void free(void *p)
{
	__libc_free(p);
}

void dao_test_alloc_start(void)
{
	atomic_store(&allocations, 0);
	atomic_store(&counting, 1);
}

long dao_test_alloc_stop(void)
{
	atomic_store(&counting, 0);
	return atomic_load(&allocations);
}
#else
void dao_test_alloc_start(void)
{
}

long dao_test_alloc_stop(void)
{
	return -1;
}
#endif
