/* SPDX-License-Identifier: MIT */
/* Large working planes on transparent huge pages where the kernel offers them (planes_alloc.h). */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS, madvise */
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>

#include "core/planes_alloc.h"

#define HUGE_PAGE ((size_t)2 << 20)

static size_t mapped_size(size_t size)
{
	return (size + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
}

void *dao_planes_alloc(size_t size)
{
	if (size == 0 || size > SIZE_MAX / 2)
		return NULL;
	if (size < HUGE_PAGE)
		return calloc(1, size);
	/* a mapping of its own (fresh zero pages, untouched until the advice
	 * is given), one huge page longer so that an aligned start exists;
	 * the slack either side is unmapped */
	const size_t len = mapped_size(size);
	unsigned char *m = mmap(NULL, len + HUGE_PAGE, PROT_READ | PROT_WRITE,
				MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
	if (m == MAP_FAILED)
		return NULL;
	const size_t lead = (HUGE_PAGE - (uintptr_t)m % HUGE_PAGE) % HUGE_PAGE;
	if (lead)
		munmap(m, lead);
	if (HUGE_PAGE - lead)
		munmap(m + lead + len, HUGE_PAGE - lead);
#ifdef MADV_HUGEPAGE
	/* advice only: where it is refused the pages stay 4 KiB */
	(void)madvise(m + lead, len, MADV_HUGEPAGE);
#endif
	return m + lead;
}

void dao_planes_free(void *p, size_t size)
{
	if (!p)
		return;
	if (size < HUGE_PAGE)
		free(p);
	else
		munmap(p, mapped_size(size));
}
