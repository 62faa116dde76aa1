/* SPDX-License-Identifier: MIT */
#ifndef DAO_TOOLS_ATOMIC_FILE_H
#define DAO_TOOLS_ATOMIC_FILE_H

#include <stddef.h>

/* Writes text + newline to path: through a temporary file renamed into place
 * (a regular file or a new path), or straight into a FIFO or character device;
 * a directory is refused (depthao/output_file.h).  Returns 0, or -1 with a message
 * (no file left behind). */
int atomic_write_text(const char *path, const char *text, char *msg, size_t len);

#endif
