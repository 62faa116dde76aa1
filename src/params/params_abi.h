/* SPDX-License-Identifier: MIT */
/*
 * How the library takes a struct dao_params from a caller that may have been
 * built against an older header (a shorter struct: fields are only appended).
 */
#ifndef DAO_PARAMS_ABI_H
#define DAO_PARAMS_ABI_H

#include <stddef.h>

#include <depthao/params.h>

/* The first struct dao_params that carried `size` (version node DEPTHAO_1):
 * every field up to occlusion_color.  Never changes once released. */
#define DAO_PARAMS_SIZE_FIRST (offsetof(struct dao_params, occlusion_color) + sizeof(uint32_t))

/* 0 if p->size is a size this library can read, else -EINVAL with a message. */
int dao_params_check_size(const struct dao_params *p, struct dao_error *err);

/* A complete struct of this library's size: the caller's fields, and the
 * defaults for the fields its struct lacks.  Checks the size, not the values. */
int dao_params_import(struct dao_params *dst, const struct dao_params *src,
		      struct dao_error *err);

/* The field at `offset` of `size` bytes is inside the caller's struct. */
static inline int dao_params_has(const struct dao_params *p, size_t offset, size_t size)
{
	return offset + size <= p->size;
}

#endif
