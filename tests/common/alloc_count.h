/* SPDX-License-Identifier: MIT */
/*
 * Counting every heap allocation the process makes (any thread, any library):
 * alloc_count.c interposes glibc's allocator.  Compile alloc_count.c into the
 * test executable itself (not through a library), so its malloc is the one
 * every caller resolves to.
 */
#ifndef DAO_TEST_ALLOC_COUNT_H
#define DAO_TEST_ALLOC_COUNT_H

#ifdef __GLIBC__
#define DAO_TEST_CAN_COUNT_ALLOCATIONS 1
#else
#define DAO_TEST_CAN_COUNT_ALLOCATIONS 0
#endif

/* Counts from 0 from now on. */
void dao_test_alloc_start(void);
/* Stops counting; the allocations since dao_test_alloc_start(). */
long dao_test_alloc_stop(void);

#endif
