/* SPDX-License-Identifier: MIT */
#include "ini_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

struct line_buf {
	char *p;
	size_t cap;
};

static int is_blank(char c)
{
	return c == ' ' || c == '\t';
}

/* Blanks off both ends, in place. */
static char *trim(char *s)
{
	while (is_blank(*s))
		s++;
	size_t n = strlen(s);
	while (n && is_blank(s[n - 1]))
		s[--n] = '\0';
	return s;
}

/* Cuts `s` at a ';' that follows a blank. */
static void cut_inline_comment(char *s)
{
	for (char *p = s; *p; p++) {
		if (*p == ';' && p > s && is_blank(p[-1])) {
			*p = '\0';
			return;
		}
	}
}

/*
 * The next line into b (without its LF or CR LF): 1, 0 at the end of the
 * file, -1 if it is longer than INI_FILE_MAX_LINE or holds a NUL byte
 * (*what says which), -2 on a read error or out of memory.
 */
static int read_line(FILE *f, struct line_buf *b, const char **what)
{
	size_t n = 0;
	int c, nul = 0;
	while ((c = getc(f)) != EOF && c != '\n') {
		if (n == INI_FILE_MAX_LINE) {
			*what = "is longer than 65536 bytes";
			return -1;
		}
		if (n + 1 >= b->cap) {
			size_t cap = b->cap ? 2 * b->cap : 256;
			char *p = realloc(b->p, cap);
			if (!p)
				return -2;
			b->p = p;
			b->cap = cap;
		}
		nul |= c == '\0';
		b->p[n++] = (char)c;
	}
	if (ferror(f))
		return -2;
	if (c == EOF && n == 0)
		return 0;
	if (n && b->p[n - 1] == '\r')
		n--;
	if (!b->p) { /* an empty last line before any buffer was needed */
		if (!(b->p = malloc(b->cap = 256)))
			return -2;
	}
	b->p[n] = '\0';
	if (nul) {
		*what = "holds a NUL byte (is this a text file?)";
		return -1;
	}
	return 1;
}

int ini_file_parse(FILE *f, ini_pair_fn on_pair, void *user, unsigned *line, char *msg,
		   size_t len)
{
	struct line_buf b = {NULL, 0};
	char *section = strdup("");
	const char *what = NULL;
	int r = 0, k;
	*line = 0;
	if (!section)
		return -2;
	while (r == 0 && (k = read_line(f, &b, &what)) != 0) {
		++*line;
		if (k == -2) {
			r = -2;
			break;
		}
		if (k == -1) {
			snprintf(msg, len, "the line %s", what);
			r = -1;
			break;
		}
		char *s = b.p;
		if (*line == 1 && !strncmp(s, "\xEF\xBB\xBF", 3))
			s += 3;
		s = trim(s);
		if (!*s || *s == ';' || *s == '#')
			continue;
		if (*s == '[') {
			char *end = strchr(s, ']');
			if (!end) {
				snprintf(msg, len, "'[' without ']': a section is [NAME]");
				r = -1;
				break;
			}
			*end = '\0';
			char *rest = trim(end + 1);
			if (*rest && *rest != ';' && *rest != '#') {
				snprintf(msg, len, "text after [%s]: a section line holds only [NAME]",
					 trim(s + 1));
				r = -1;
				break;
			}
			char *name = strdup(trim(s + 1));
			if (!name) {
				r = -2;
				break;
			}
			free(section);
			section = name;
			continue;
		}
		char *eq = strchr(s, '=');
		if (!eq || eq == s) {
			snprintf(msg, len, "not 'key = value' or '[section]'");
			r = -1;
			break;
		}
		*eq = '\0';
		char *value = eq + 1;
		cut_inline_comment(value);
		if (on_pair(user, section, trim(s), trim(value), msg, len) < 0)
			r = -1;
	}
	int e = errno;
	free(b.p);
	free(section);
	errno = e;
	return r;
}
