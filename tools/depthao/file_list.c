/* SPDX-License-Identifier: MIT */
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "file_list.h"

static int has_png_suffix(const char *name)
{
	size_t n = strlen(name);
	return n > 4 && (strcmp(name + n - 4, ".png") == 0 || strcmp(name + n - 4, ".PNG") == 0);
}

static int cmp_names(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

int file_list_pngs(const char *dir, struct file_list *out)
{
	out->names = NULL;
	out->count = 0;
	DIR *d = opendir(dir);
	if (!d)
		return -errno;
	size_t cap = 0;
	struct dirent *e;
	while ((e = readdir(d))) {
		if (!has_png_suffix(e->d_name))
			continue;
		char *full = path_join(dir, e->d_name);
		struct stat st;
		int regular = full && stat(full, &st) == 0 && S_ISREG(st.st_mode);
		free(full);
		if (!regular)
			continue;
		if (out->count == cap) {
			cap = cap ? 2 * cap : 64;
			char **n = realloc(out->names, cap * sizeof *n);
			if (!n)
				goto nomem;
			out->names = n;
		}
		if (!(out->names[out->count] = strdup(e->d_name)))
			goto nomem;
		out->count++;
	}
	closedir(d);
	if (out->count)
		qsort(out->names, out->count, sizeof *out->names, cmp_names);
	return 0;
nomem:
	closedir(d);
	file_list_free(out);
	return -ENOMEM;
}

void file_list_free(struct file_list *l)
{
	for (size_t i = 0; i < l->count; i++)
		free(l->names[i]);
	free(l->names);
	l->names = NULL;
	l->count = 0;
}

int path_is_dir(const char *path)
{
	struct stat st;
	if (stat(path, &st) != 0)
		return -errno;
	return S_ISDIR(st.st_mode) ? 1 : 0;
}

char *path_join(const char *dir, const char *name)
{
	size_t a = strlen(dir), b = strlen(name);
	char *s = malloc(a + b + 2);
	if (!s)
		return NULL;
	memcpy(s, dir, a);
	size_t k = a;
	if (a && dir[a - 1] != '/')
		s[k++] = '/';
	memcpy(s + k, name, b + 1);
	return s;
}

char *path_dirname(const char *path)
{
	const char *slash = strrchr(path, '/');
	if (!slash)
		return strdup(".");
	if (slash == path)
		return strdup("/");
	size_t n = (size_t)(slash - path);
	char *s = malloc(n + 1);
	if (s) {
		memcpy(s, path, n);
		s[n] = '\0';
	}
	return s;
}

const char *path_basename(const char *path)
{
	const char *slash = strrchr(path, '/');
	return slash ? slash + 1 : path;
}
