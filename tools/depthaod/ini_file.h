/* SPDX-License-Identifier: MIT */
/*
 * The INI syntax of depthaod's configuration, read line by line with no
 * limit on line length below INI_FILE_MAX_LINE, and every error reported
 * at the line where it is:
 *   - lines end with LF (a CR before it is dropped); a UTF-8 byte order mark
 *     at the start of the file is skipped; blanks (space, tab) around
 *     everything are ignored, indentation included;
 *   - empty lines and lines starting with ';' or '#' are comments;
 *   - "[NAME]" starts a section (only blanks or a ';' comment may follow);
 *   - "KEY = VALUE": the key is what precedes the first '=', the value what
 *     follows it up to a ';' that comes after a blank (an inline comment);
 *     the value may be empty, keys outside any section have section "".
 * It accepts what libinih (the parser depthaod used before) accepted in the
 * example configuration, without its 200-byte line limit and its
 * continuation lines.
 */
#ifndef DAOD_INI_FILE_H
#define DAOD_INI_FILE_H

#include <stddef.h>
#include <stdio.h>

#define INI_FILE_MAX_LINE 65536

/* One pair; 0 to go on, or < 0 with a message in msg (the parse stops there). */
typedef int (*ini_pair_fn)(void *user, const char *section, const char *key, const char *value,
			   char *msg, size_t len);

/*
 * Reads `f` to the end, calling `on_pair` for each pair in order.  Returns
 * 0; or -1 with *line the 1-based line of the first error and msg what is
 * wrong there (a syntax error, or on_pair's message); or -2 on a read error
 * or out of memory (errno set, *line the line being read).
 */
int ini_file_parse(FILE *f, ini_pair_fn on_pair, void *user, unsigned *line, char *msg,
		   size_t len);

#endif
