/* SPDX-License-Identifier: MIT */
/* Sizes of struct dao_params across versions (see params_abi.h). */
#include "params/params_abi.h"

#include <errno.h>
#include <string.h>

#include "core/error_internal.h"
#include "params/presets.h"

static int size_ok(size_t size)
{
	return size >= DAO_PARAMS_SIZE_FIRST && size <= sizeof(struct dao_params);
}

int dao_params_check_size(const struct dao_params *p, struct dao_error *err)
{
	if (!p)
		return dao_error_set(err, -EINVAL, "parameters are NULL");
	if (!size_ok(p->size))
		return dao_error_set(err, -EINVAL,
				     "struct dao_params has size %u, this library reads %zu to %zu "
				     "bytes: fill it with dao_params_init() (a struct set up by hand "
				     "or copied from a newer depthao has no valid size)",
				     (unsigned)p->size, (size_t)DAO_PARAMS_SIZE_FIRST,
				     sizeof(struct dao_params));
	return 0;
}

int dao_params_import(struct dao_params *dst, const struct dao_params *src,
		      struct dao_error *err)
{
	int r = dao_params_check_size(src, err);
	if (r < 0)
		return r;
	dao_preset_fill(dst, DAO_QUALITY_DEFAULT);
	memcpy(dst, src, src->size);
	dst->size = sizeof(*dst);
	return 0;
}

int dao_params_init_sized(struct dao_params *p, size_t size, enum dao_quality q)
{
	if (!p || !size_ok(size))
		return -EINVAL;
	if ((unsigned)q >= DAO_QUALITY_COUNT)
		q = DAO_QUALITY_DEFAULT;
	struct dao_params full;
	dao_preset_fill(&full, q);
	memcpy(p, &full, size);
	p->size = (uint32_t)size;
	return 0;
}
