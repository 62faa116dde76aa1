/* SPDX-License-Identifier: MIT */
#define _XOPEN_SOURCE 700
#include <ftw.h>
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

/* the directories made by dao_test_tmpdir, removed when the test exits */
#define MAX_TMPDIRS 64
static char tmpdirs[MAX_TMPDIRS][512];
static int n_tmpdirs;
static pid_t tmpdir_owner;

static int remove_entry(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
	(void)st, (void)type, (void)ftw;
	if (remove(path) != 0)
		fprintf(stderr, "test clean-up: cannot remove %s\n", path);
	return 0;
}

static void remove_tmpdirs(void)
{
	/* a forked child that exits must not take its parent's directories with it */
	if (getpid() != tmpdir_owner || getenv("DAO_TEST_KEEP_TMP"))
		return;
	for (int i = 0; i < n_tmpdirs; i++)
		nftw(tmpdirs[i], remove_entry, 16, FTW_DEPTH | FTW_PHYS);
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
	if (n_tmpdirs == 0) {
		tmpdir_owner = getpid();
		atexit(remove_tmpdirs);
	}
	if (n_tmpdirs < MAX_TMPDIRS)
		snprintf(tmpdirs[n_tmpdirs++], sizeof tmpdirs[0], "%s", path);
	return path;
}
