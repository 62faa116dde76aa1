/* SPDX-License-Identifier: MIT */
/* Large working planes on transparent huge pages where the kernel offers them (planes_alloc.h). */
#define _DEFAULT_SOURCE /* madvise */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "core/planes_alloc.h"

#define HUGE_PAGE ((size_t)2 << 20)

void *dao_planes_alloc(size_t size, int zero)
{
	if (size == 0)
		return NULL;
	if (size < HUGE_PAGE || size > SIZE_MAX - HUGE_PAGE)
		return zero ? calloc(1, size) : malloc(size);
	/* C11's aligned_alloc wants a multiple of the alignment */
	const size_t rounded = (size + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
	void *p = aligned_alloc(HUGE_PAGE, rounded);
	if (!p)
		return NULL;
#ifdef MADV_HUGEPAGE
	/* advice only: where it is refused the pages stay 4 KiB */
	(void)madvise(p, rounded, MADV_HUGEPAGE);
#endif
	if (zero)
		memset(p, 0, size);
	return p;
}
