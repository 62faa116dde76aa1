/* SPDX-License-Identifier: MIT */
/*
 * Every parameter of every quality preset, and of the stream defaults on top
 * of each, printed exactly (floats to 9 significant digits, which round-trip
 * a float) and compared with a committed expectation.  The expectation was
 * printed by the build before the defaults moved into the parameter table,
 * so any default that changes by accident fails here.
 *
 *   test-param-defaults EXPECTED   compare (the test)
 *   test-param-defaults --dump     print the dump (to make the expectation)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/params.h>

/* The dump of one parameter set, one "label name value" line per parameter. */
static size_t dump_params(char *buf, size_t cap, const char *label, const struct dao_params *p)
{
	size_t count, used = 0;
	const struct dao_param_info *t = dao_param_table(&count);
	for (size_t i = 0; i < count; i++) {
		const void *f = (const char *)p + t[i].offset;
		int n = 0;
		switch (t[i].type) {
		case DAO_PARAM_FLOAT: {
			float v;
			memcpy(&v, f, sizeof v);
			n = snprintf(buf + used, cap - used, "%s %s %.9g\n", label, t[i].name, (double)v);
			break;
		}
		case DAO_PARAM_INT:
		case DAO_PARAM_ENUM: {
			int v;
			memcpy(&v, f, sizeof v);
			n = snprintf(buf + used, cap - used, "%s %s %d\n", label, t[i].name, v);
			break;
		}
		case DAO_PARAM_COLOR: {
			uint32_t v;
			memcpy(&v, f, sizeof v);
			n = snprintf(buf + used, cap - used, "%s %s %06x\n", label, t[i].name,
				     (unsigned)v);
			break;
		}
		}
		if (n < 0 || (size_t)n >= cap - used) {
			fprintf(stderr, "dump buffer too small\n");
			exit(1);
		}
		used += (size_t)n;
	}
	return used;
}

static char *dump_all(size_t *len)
{
	size_t cap = 1 << 20, used = 0;
	char *buf = malloc(cap);
	if (!buf)
		exit(1);
	buf[0] = '\0';
	for (int q = 0; q < DAO_QUALITY_COUNT; q++) {
		struct dao_params p;
		char label[64];
		dao_params_init(&p, (enum dao_quality)q);
		snprintf(label, sizeof label, "%s", dao_quality_name((enum dao_quality)q));
		used += dump_params(buf + used, cap - used, label, &p);
		dao_params_stream_defaults(&p);
		snprintf(label, sizeof label, "%s+stream", dao_quality_name((enum dao_quality)q));
		used += dump_params(buf + used, cap - used, label, &p);
	}
	struct dao_params d;
	dao_params_init(&d, DAO_QUALITY_DEFAULT);
	used += dump_params(buf + used, cap - used, "default", &d);
	*len = used;
	return buf;
}

int main(int argc, char **argv)
{
	size_t len;
	char *now = dump_all(&len);
	if (argc == 2 && !strcmp(argv[1], "--dump")) {
		fwrite(now, 1, len, stdout);
		free(now);
		return 0;
	}
	if (argc != 2) {
		fprintf(stderr, "usage: %s EXPECTED | --dump\n", argv[0]);
		return 2;
	}
	FILE *f = fopen(argv[1], "rb");
	if (!f) {
		perror(argv[1]);
		return 1;
	}
	char *want = malloc(len + 2);
	size_t got = want ? fread(want, 1, len + 1, f) : 0;
	fclose(f);
	int ok = want && got == len && !memcmp(want, now, len);
	if (!ok) {
		/* the first line that differs, for the log */
		const char *a = now, *b = want ? want : "";
		size_t i = 0;
		while (i < len && i < got && a[i] == b[i])
			i++;
		while (i > 0 && a[i - 1] != '\n')
			i--;
		fprintf(stderr, "parameter defaults differ from %s at:\n  now:      %.*s\n"
			"  expected: %.*s\n", argv[1], (int)strcspn(a + i, "\n"), a + i,
			i < got ? (int)strcspn(b + i, "\n") : 0, i < got ? b + i : "");
	}
	free(want);
	free(now);
	return ok ? 0 : 1;
}
