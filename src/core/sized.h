/* SPDX-License-Identifier: MIT */
/*
 * Structs that begin with `uint32_t size` (docs/abi.md): the caller's struct
 * may be shorter (built against an older header) or longer (a newer one)
 * than the library's, and the library touches no byte past either.
 */
#ifndef DAO_CORE_SIZED_H
#define DAO_CORE_SIZED_H

#include <errno.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* One past the last byte of `field` in `type`. */
#define DAO_END_OF(type, field) (offsetof(type, field) + sizeof(((type *)0)->field))

/*
 * Copies the library's struct `src` (`src_size` bytes, its own `size` field
 * ignored) into the caller's `out` of `out_size` bytes: the first
 * min(out_size, src_size) bytes, nothing past them, and that count into
 * out->size.  -EINVAL (nothing written) if `out` is NULL or cannot hold the
 * size field itself.
 */
static inline int dao_sized_copy_out(void *out, size_t out_size, const void *src, size_t src_size)
{
	if (!out || !src || out_size < sizeof(uint32_t))
		return -EINVAL;
	size_t n = out_size < src_size ? out_size : src_size;
	memcpy(out, src, n);
	const uint32_t filled = (uint32_t)n;
	memcpy(out, &filled, sizeof filled);
	return 0;
}

/*
 * Takes the caller's struct `in` (whose leading `size` says how long it is)
 * into the library's `dst` of `dst_size` bytes: the caller's bytes, zeros
 * for the fields its struct lacks, dst's size field set to dst_size.  The
 * caller's size must be at least `first` (the first layout that carried a
 * size) and at most dst_size (a newer program's struct: settings this
 * library cannot honour).  0, -EINVAL with nothing written otherwise.
 */
static inline int dao_sized_copy_in(void *dst, size_t dst_size, const void *in, size_t first)
{
	uint32_t size;
	if (!in)
		return -EINVAL;
	memcpy(&size, in, sizeof size);
	if (size < first || size > dst_size)
		return -EINVAL;
	memset(dst, 0, dst_size);
	memcpy(dst, in, size);
	const uint32_t full = (uint32_t)dst_size;
	memcpy(dst, &full, sizeof full);
	return 0;
}

#endif
