/* SPDX-License-Identifier: MIT */
/* Part of libdepthao-io (pkg-config depthao-io, <depthao/io.h>), not of the AO core libdepthao. */
/*
 * Opening a path for a file written whole (a PNG, a small text file, a point
 * cloud), as depthao's own outputs are written; what
 * the path already is decides how:
 *   - nothing, or a regular file: a temporary file beside it, renamed into
 *     place once complete, so readers never see half a file and a failed
 *     write leaves the old one;
 *   - a symlink to a regular file: the same at the file it points to (the
 *     link stays a link);
 *   - a FIFO or a character device (/dev/stdout on a pipe or a terminal,
 *     /dev/null, a serial line): written straight into, opened without
 *     O_CREAT or O_TRUNC, never replaced; a FIFO without a reader is -ENXIO
 *     at once instead of a hang;
 *   - a directory: -EISDIR; a block device or a socket: -EINVAL;
 *   - "-": standard output, written straight into like a FIFO; -EINVAL when
 *     it is a terminal;
 *   - a regular file that could not be written in place (no write bit in its
 *     mode, even for root, or not writable by this user): -EACCES, never
 *     replaced;
 *   - a symlink to nothing (dangling): -ENOENT, nothing created.
 */
#ifndef DEPTHAO_OUTPUT_FILE_H
#define DEPTHAO_OUTPUT_FILE_H

#include <stdint.h>

#include <depthao/error.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Opaque: what is written where (the fd, a temporary name, the target). */
struct dao_output_file;

/*
 * Opens `path` for writing as above into a new *out; messages name `path`.
 * Write through dao_output_file_fd(), close that fd, then end with exactly
 * one of dao_output_file_commit() or dao_output_file_discard(), which free
 * *out.  0, or a negative errno with *out NULL.
 */
DAO_API int dao_output_file_open(struct dao_output_file **out, const char *path,
				 struct dao_error *err);

/* The descriptor to write to; the caller closes it before commit or discard. */
DAO_API int dao_output_file_fd(const struct dao_output_file *o);

/* After the last byte was written and the fd closed: renames into place (if
 * temporary) and frees `o`. */
DAO_API int dao_output_file_commit(struct dao_output_file *o, struct dao_error *err);

/* After a failure (fd closed): removes the temporary file (the target is
 * untouched) and frees `o`; NULL-safe. */
DAO_API void dao_output_file_discard(struct dao_output_file *o);

/*
 * Input files (every file depthao reads: PNG, .oni, bags, camera and
 * configuration files) go through one gate: opens `path` for reading and
 * returns the descriptor (O_CLOEXEC, blocking), or a negative errno with a
 * message naming `what` ("camera file"), the path and what it is.  It must
 * be a regular file (or a symlink to one): a FIFO, a directory, a device or
 * a socket is -EINVAL, decided without reading (a FIFO never hangs the
 * reader); with max_size > 0 a larger file is -EFBIG, unread.
 * *size (may be NULL) gets the file's size.
 */
DAO_API int dao_input_file_open(const char *path, const char *what, uint64_t max_size,
				uint64_t *size, struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
