/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is a depthaod configuration file.  It is read
 * twice: by ini_file_parse() alone, whose pairs must be well formed (no line
 * breaks, no blanks around keys and values, a key that is not empty), and by
 * config_load() + config_check() as the daemon reads it.  Any outcome is fine
 * except a crash, a sanitizer report, or an error without a message or line.
 */
#define _GNU_SOURCE /* fmemopen */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../tools/depthaod/config.h"
#include "../tools/depthaod/ini_file.h"
#include "harness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int blank(char c)
{
	return c == ' ' || c == '\t';
}

/* Checks one pair; every 7th pair is refused, to walk the callback's error path. */
static int check_pair(void *user, const char *section, const char *key, const char *value,
		      char *msg, size_t len)
{
	unsigned *n = user;
	size_t kl = strlen(key), vl = strlen(value);
	if (!kl || blank(key[0]) || blank(key[kl - 1]) || (vl && (blank(value[0]) ||
	    blank(value[vl - 1]))))
		abort();
	if (strchr(section, '\n') || strchr(key, '\n') || strchr(value, '\n'))
		abort();
	if (++*n % 7 == 0) {
		snprintf(msg, len, "refused");
		return -1;
	}
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char msg[600] = "";
	unsigned line = 0, n = 0;
	FILE *f = fmemopen((void *)data, size ? size : 1, "r");
	if (!f)
		return 0;
	if (!size)
		fgetc(f); /* an empty input: fmemopen needs a size of at least 1 */
	int r = ini_file_parse(f, check_pair, &n, &line, msg, sizeof msg);
	fclose(f);
	if (r == -1 && (!line || !msg[0]))
		abort();

	static struct fuzz_file file;
	fuzz_file_store(&file, "fuzz-ini", NULL, data, size);
	struct daemon_config *c = malloc(sizeof *c);
	if (!c)
		abort();
	config_defaults(c);
	msg[0] = 0;
	r = config_load(c, file.path, msg, sizeof msg);
	if (r < 0 && !msg[0])
		abort();
	if (r == 0) {
		msg[0] = 0;
		if (config_check(c, msg, sizeof msg) < 0 && !msg[0])
			abort();
	}
	free(c);
	return 0;
}
