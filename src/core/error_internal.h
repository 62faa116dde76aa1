/* SPDX-License-Identifier: MIT */
/* The library's files include this; dao_error_set() and dao_error_clear() are
 * public (depthao/error.h), so plugins and tools report errors the same way. */
#ifndef DAO_CORE_ERROR_INTERNAL_H
#define DAO_CORE_ERROR_INTERNAL_H

#include <depthao/error.h>

#endif
