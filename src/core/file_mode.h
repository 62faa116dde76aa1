/* SPDX-License-Identifier: MIT */
#ifndef DAO_CORE_FILE_MODE_H
#define DAO_CORE_FILE_MODE_H

#include <sys/stat.h>

/*
 * mkstemp() creates files 0600; before a temporary file is renamed into
 * place it gets the permissions a plain fopen() would have given it.
 */
static inline void dao_file_mode_default(const char *path)
{
	mode_t mask = umask(0);
	umask(mask);
	chmod(path, 0666 & ~mask);
}

#endif
