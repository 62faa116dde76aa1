/* SPDX-License-Identifier: MIT */
/*
 * Working planes of a frame: large buffers the passes walk down columns and
 * along slices, a row (often a 4 KiB page or more) per step.  With 4 KiB
 * pages such a walk needs a new TLB entry nearly every step; on 2 MiB pages
 * a VGA plane is one (docs/perf/hugepages.md).  dao_planes_alloc maps
 * buffers of 2 MiB or more on their own, 2 MiB aligned, and asks the kernel
 * for transparent huge pages there before the first touch
 * (madvise(MADV_HUGEPAGE): honoured where
 * /sys/kernel/mm/transparent_hugepage/enabled says always or madvise,
 * ignored otherwise); smaller ones come from malloc.
 */
#ifndef DAO_CORE_PLANES_ALLOC_H
#define DAO_CORE_PLANES_ALLOC_H

#include <stddef.h>

/* `size` bytes, zeroed; NULL when out of memory or size is 0 */
void *dao_planes_alloc(size_t size);

/* releases what dao_planes_alloc(size) returned (NULL: nothing) */
void dao_planes_free(void *p, size_t size);

#endif
