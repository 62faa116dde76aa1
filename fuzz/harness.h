/* SPDX-License-Identifier: MIT */
/*
 * What the file-reading fuzz targets share (harness.c): the input stored in a
 * file that a reader opens by path, the check that an error is documented and
 * has a message, and a source played to its end twice.  Every failed check
 * aborts, which libFuzzer reports as a crash with the input that caused it.
 */
#ifndef DAO_FUZZ_HARNESS_H
#define DAO_FUZZ_HARNESS_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

/* A file rewritten with every input: a memfd, opened by its /proc/self/fd path,
 * or (where memfds cannot be opened so) NAME in fuzz_temp_dir(). */
struct fuzz_file {
	int fd;         /* the memfd, or -1 */
	char path[128]; /* what the reader opens */
	char uri[160];  /* SCHEME:path (or the path), what a source opens */
};

/* A directory made once per run in /tmp, for the files a target writes. */
const char *fuzz_temp_dir(void);

/* Replaces the file's bytes with the input's; the first call makes the file (NAME
 * also names the memfd) and its URI (SCHEME:path, or the path when SCHEME is NULL). */
void fuzz_file_store(struct fuzz_file *f, const char *name, const char *scheme,
		     const uint8_t *data, size_t size);

/* Writes PATH with the input's bytes. */
void fuzz_write_file(const char *path, const uint8_t *data, size_t size);

/* ret < 0 must be one of `codes` (negative errno values, ended by 0) and be
 * err's code, with a message. */
void fuzz_check_error(int ret, const struct dao_error *err, const int *codes);

/* Plays URI as a source of at most MAX_PIXELS pixels (the built-in plugins):
 * every frame, a seek back to the start, every frame again.  An open that
 * fails must fail by fuzz_check_error(); an open that succeeds must report
 * FRAMES frames (or at least one when FRAMES is 0), a size within the limit
 * and a terminated description, start, give frames of that size and format
 * (or errors by fuzz_check_error()) and seek.  Every frame's camera pose is
 * asked for (dao_source_frame_pose: the recording's tf, odometry or Foxglove
 * transforms): a finite unit pose, or an error with a message and one of
 * the codes the poses document. */
void fuzz_play_source(const char *uri, uint64_t max_pixels, int64_t frames, const int *codes);

#endif
