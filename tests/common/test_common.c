/* SPDX-License-Identifier: MIT */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/test_common.h"

int dao_test_data_path(const char *rel, char *buf, size_t len)
{
	const char *root = getenv("DAO_SHARED_DATA");
	if (!root)
		root = "../shared/data";
	snprintf(buf, len, "%s/%s", root, rel);
	return access(buf, R_OK) == 0 ? 0 : -1;
}

const char *dao_test_tmpdir(const char *tag)
{
	static char path[512];
	const char *base = getenv("TMPDIR");
	if (!base)
		base = "/tmp";
	snprintf(path, sizeof path, "%s/dao-test-%s-XXXXXX", base, tag);
	if (!mkdtemp(path)) {
		perror("mkdtemp");
		exit(1);
	}
	return path;
}
