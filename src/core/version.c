/* SPDX-License-Identifier: MIT */
#include <depthao/depthao.h>

const char *dao_version(void)
{
	return DAO_VERSION_STRING;
}
