/* SPDX-License-Identifier: MIT */
/*
 * Working planes of a frame: large buffers the passes walk down columns and
 * along slices, a row (often a 4 KiB page or more) per step.  With 4 KiB
 * pages such a walk needs a new TLB entry nearly every step; on 2 MiB pages
 * a VGA plane is one.  dao_planes_alloc aligns buffers of 2 MiB or more to
 * 2 MiB and asks the kernel for transparent huge pages there
 * (madvise(MADV_HUGEPAGE): honoured where
 * /sys/kernel/mm/transparent_hugepage/enabled says always or madvise,
 * ignored otherwise); free() releases them.
 */
#ifndef DAO_CORE_PLANES_ALLOC_H
#define DAO_CORE_PLANES_ALLOC_H

#include <stddef.h>

/* `size` bytes, zeroed when `zero`; NULL when out of memory or size is 0 */
void *dao_planes_alloc(size_t size, int zero);

#endif
