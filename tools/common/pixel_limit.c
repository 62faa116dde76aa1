/* SPDX-License-Identifier: MIT */
#include "pixel_limit.h"

#include <errno.h>
#include <stdlib.h>

#include <depthao/frame.h>

static int parse_count(const char *s, char **end, uint64_t *out)
{
	if (*s < '0' || *s > '9')
		return -1;
	errno = 0;
	unsigned long long n = strtoull(s, end, 10);
	if (errno)
		return -1;
	*out = n;
	return 0;
}

int pixel_limit_parse(const char *text, uint64_t *out)
{
	const uint64_t most = (uint64_t)DAO_MAX_DIMENSION * DAO_MAX_DIMENSION;
	char *end;
	uint64_t n, h;
	if (parse_count(text, &end, &n))
		return -1;
	if (*end == 'x') {
		if (parse_count(end + 1, &end, &h) || n > DAO_MAX_DIMENSION || h > DAO_MAX_DIMENSION)
			return -1;
		n *= h;
	}
	if (*end || n < 1 || n > most)
		return -1;
	*out = n;
	return 0;
}
