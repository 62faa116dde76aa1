/* SPDX-License-Identifier: MIT */
#ifndef DAO_TOOLS_FILE_LIST_H
#define DAO_TOOLS_FILE_LIST_H

#include <stddef.h>

struct file_list {
	char **names;  /* file names (no directory), sorted */
	size_t count;
};

/* The *.png files of a directory, sorted by name.  Returns 0, or -errno. */
int file_list_pngs(const char *dir, struct file_list *out);

void file_list_free(struct file_list *l);

/* 1 if path is a directory, 0 if something else exists there, -errno if it cannot be read. */
int path_is_dir(const char *path);

/* "dir/name" in a newly allocated string (NULL on out of memory). */
char *path_join(const char *dir, const char *name);

/* The directory part of a path ("." if none), newly allocated. */
char *path_dirname(const char *path);

/* The last component of a path. */
const char *path_basename(const char *path);

#endif
