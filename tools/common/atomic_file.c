/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <depthao/error.h>

#include "common/atomic_file.h"
#include <depthao/output_file.h>

int atomic_write_text(const char *path, const char *text, char *msg, size_t len)
{
	struct dao_output_file *out;
	struct dao_error err = {0};
	if (dao_output_file_open(&out, path, &err) < 0) {
		snprintf(msg, len, "%s", err.message);
		return -1;
	}
	FILE *f = fdopen(dao_output_file_fd(out), "w");
	int ok = f && fputs(text, f) >= 0 && fputc('\n', f) != EOF;
	int e = errno;
	if (f) {
		if (fclose(f) != 0 && ok) {
			ok = 0;
			e = errno;
		}
	} else {
		close(dao_output_file_fd(out));
	}
	if (!ok) {
		snprintf(msg, len, "cannot write '%s': %s", path, strerror(e));
		dao_output_file_discard(out);
		return -1;
	}
	if (dao_output_file_commit(out, &err) < 0) {
		snprintf(msg, len, "%s", err.message);
		return -1;
	}
	return 0;
}
