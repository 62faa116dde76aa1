/* SPDX-License-Identifier: MIT */
/*
 * The library's own writers (PNG, PLY) keep a struct dao_output_file inside
 * their state; programs get the opaque handle of depthao/output_file.h.
 */
#ifndef DAO_IO_OUTPUT_FILE_INTERNAL_H
#define DAO_IO_OUTPUT_FILE_INTERNAL_H

#include <depthao/output_file.h>

struct dao_output_file {
	int fd;         /* write here; the caller closes it before finish/abandon */
	char *tmp;      /* the temporary file, NULL when written straight into the target */
	char *target;   /* what tmp is renamed onto (a symlink resolved) */
	char *path;     /* the handle's path (dao_output_file_open); NULL inside the library */
};

struct stat;
/*
 * The one rule for replacing an existing regular file (st: stat of path):
 * -EACCES with a message unless it could be written in place (a w bit in
 * its mode, even for root, and access(W_OK)).  The recorders' overwrite
 * applies it too.
 */
int dao_output_file_check_replaceable(const char *path, const struct stat *st,
				      struct dao_error *err);

/* dao_output_file_open() into `o` (not allocated); messages name `path`. */
int dao_output_file_begin(struct dao_output_file *o, const char *path, struct dao_error *err);
/* After the last byte was written and fd closed: renames into place (if temporary). */
int dao_output_file_finish(struct dao_output_file *o, const char *path, struct dao_error *err);
/* After a failure (fd closed): removes the temporary file; the target is untouched. */
void dao_output_file_abandon(struct dao_output_file *o);

#endif
