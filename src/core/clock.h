/* SPDX-License-Identifier: MIT */
/* The monotonic clock and sleeping, in one place for the library. */
#ifndef DAO_CORE_CLOCK_H
#define DAO_CORE_CLOCK_H

#include <errno.h>
#include <stdint.h>
#include <time.h>

/* CLOCK_MONOTONIC in nanoseconds. */
static inline uint64_t dao_mono_ns(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

/* Microseconds since `since_ns` (a dao_mono_ns() value); negative if it is ahead. */
static inline int64_t dao_mono_us_since(uint64_t since_ns)
{
	return ((int64_t)dao_mono_ns() - (int64_t)since_ns) / 1000;
}

/* Sleeps `us` microseconds (nothing if <= 0), resumed after signals. */
static inline void dao_sleep_us(int64_t us)
{
	if (us <= 0)
		return;
	struct timespec d = { (time_t)(us / 1000000), (long)(us % 1000000) * 1000 };
	while (nanosleep(&d, &d) < 0 && errno == EINTR)
		;
}

#endif
