/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic_file.h"

int atomic_write_text(const char *path, const char *text, char *msg, size_t len)
{
	size_t n = strlen(path) + 16;
	char *tmp = malloc(n);
	if (!tmp) {
		snprintf(msg, len, "out of memory writing '%s'", path);
		return -1;
	}
	snprintf(tmp, n, "%s.tmp-XXXXXX", path);
	int fd = mkstemp(tmp);
	if (fd < 0) {
		snprintf(msg, len, "cannot create '%s': %s", path, strerror(errno));
		free(tmp);
		return -1;
	}
	FILE *f = fdopen(fd, "w");
	int ok = f && fputs(text, f) >= 0 && fputc('\n', f) != EOF;
	int e = errno;
	if (f) {
		if (fclose(f) != 0 && ok) {
			ok = 0;
			e = errno;
		}
	} else {
		close(fd);
	}
	if (ok) {
		mode_t mask = umask(0);
		umask(mask);
		chmod(tmp, 0666 & ~mask);
		if (rename(tmp, path) != 0) {
			ok = 0;
			e = errno;
		}
	}
	if (!ok) {
		snprintf(msg, len, "cannot write '%s': %s", path, strerror(e));
		unlink(tmp);
	}
	free(tmp);
	return ok ? 0 : -1;
}
