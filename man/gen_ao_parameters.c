/* SPDX-License-Identifier: MIT */
/*
 * Writes a manual page with its AO PARAMETERS list made from the library's
 * parameter table (dao_param_table), so the page cannot drift from the
 * options: copies IN to OUT, replacing the line `.\" AO-PARAMETERS-LIST` with
 * one tagged paragraph per parameter (option, help, range or values, the
 * default preset's value).
 * usage: gen_ao_parameters IN OUT
 */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include <depthao/depthao.h>

#define MARKER ".\\\" AO-PARAMETERS-LIST"
#define WRAP 78

/* Roff text: a backslash as \e; with `minus`, a hyphen as \- (what is typed: options,
 * values), else left a hyphen (prose). */
static void put_roff(FILE *o, const char *s, size_t n, int minus)
{
	for (size_t i = 0; i < n; i++) {
		if (s[i] == '\\')
			fputs("\\e", o);
		else if (s[i] == '-' && minus)
			fputs("\\-", o);
		else
			fputc(s[i], o);
	}
}

static void put_escaped(FILE *o, const char *s, size_t n)
{
	put_roff(o, s, n, 1);
}

/* The help sentence, capitalised and ended with a full stop, wrapped at word boundaries
 * (a line that would start with . or ' gets \& before it). */
static void put_help(FILE *o, const char *help)
{
	char buf[512];
	size_t n = (size_t)snprintf(buf, sizeof buf, "%s", help);
	if (n >= sizeof buf)
		n = sizeof buf - 1;
	buf[0] = (char)toupper((unsigned char)buf[0]);
	if (n && buf[n - 1] != '.' && n + 1 < sizeof buf) {
		buf[n++] = '.';
		buf[n] = 0;
	}
	const char *p = buf;
	while (*p) {
		size_t len = strlen(p);
		if (len > WRAP) {
			len = WRAP;
			while (len > 0 && p[len] != ' ')
				len--;
			if (!len)
				len = strcspn(p, " ");
		}
		put_roff(o, p, len, 0);
		fputc('\n', o);
		p += len;
		while (*p == ' ')
			p++;
		if (*p == '.' || *p == '\'')
			fputs("\\&", o);
	}
}

static void put_number(FILE *o, double v)
{
	char b[64];
	snprintf(b, sizeof b, "%g", v);
	put_escaped(o, b, strlen(b));
}

static int put_parameters(FILE *o)
{
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	size_t count;
	const struct dao_param_info *t = dao_param_table(&count);
	for (size_t i = 0; i < count; i++) {
		char def[128];
		if (dao_params_get(&p, t[i].name, def, sizeof def, NULL) < 0) {
			fprintf(stderr, "gen_ao_parameters: no value for '%s'\n", t[i].name);
			return -1;
		}
		fputs(".TP\n.BI \\-\\-", o);
		put_escaped(o, t[i].name, strlen(t[i].name));
		fputs(" \" VALUE\"\n", o);
		put_help(o, t[i].help);
		fputs("Values ", o);
		switch (t[i].type) {
		case DAO_PARAM_FLOAT:
		case DAO_PARAM_INT:
			put_number(o, t[i].min);
			fputs("..", o);
			put_number(o, t[i].max);
			if (t[i].unit) {
				fputc(' ', o);
				put_escaped(o, t[i].unit, strlen(t[i].unit));
			}
			break;
		case DAO_PARAM_ENUM:
			for (const char *const *e = t[i].enum_names; *e; e++) {
				put_escaped(o, *e, strlen(*e));
				if (e[1])
					fputs(", ", o);
			}
			break;
		case DAO_PARAM_COLOR:
			fputs("RRGGBB", o);
			break;
		}
		fputs("; default ", o);
		put_escaped(o, def, strlen(def));
		fputs(".\n", o);
	}
	return 0;
}

int main(int argc, char **argv)
{
	if (argc != 3) {
		fprintf(stderr, "usage: gen_ao_parameters IN OUT\n");
		return 2;
	}
	FILE *in = fopen(argv[1], "r"), *out = fopen(argv[2], "w");
	if (!in || !out) {
		perror(in ? argv[2] : argv[1]);
		return 1;
	}
	char line[4096];
	int found = 0;
	while (fgets(line, sizeof line, in)) {
		if (!strncmp(line, MARKER, strlen(MARKER))) {
			if (put_parameters(out) < 0)
				return 1;
			found++;
		} else {
			fputs(line, out);
		}
	}
	if (found != 1) {
		fprintf(stderr, "gen_ao_parameters: %s: expected one '%s' line, found %d\n", argv[1],
			MARKER, found);
		return 1;
	}
	if (ferror(in) || fclose(out) != 0) {
		perror(argv[2]);
		return 1;
	}
	fclose(in);
	return 0;
}
