/* SPDX-License-Identifier: MIT */
/* Helpers shared by the test programs. */
#ifndef DAO_TEST_COMMON_H
#define DAO_TEST_COMMON_H

#include <stddef.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

/* Exit code that makes meson report SKIP. */
#define DAO_TEST_SKIP 77

/*
 * Path of a file under ../shared/data (from $DAO_SHARED_DATA), written to
 * buf.  Returns 0 if the file exists, -1 otherwise (the caller skips).
 */
int dao_test_data_path(const char *rel, char *buf, size_t len);

/*
 * A fresh empty directory under $TMPDIR (or /tmp); returns its path (static).
 * It and what it holds are removed when the test exits (exit or return from
 * main), unless DAO_TEST_KEEP_TMP is set (to look at what a test wrote).
 */
const char *dao_test_tmpdir(const char *tag);

/*
 * The AO of a float depth image (metres, cam's size) from a context at the
 * default preset with `algorithm` and VBAO's thickness mode and constant, on
 * 2 threads: a plane of width x height floats the caller frees, or NULL
 * after printing why (the caller asserts it).
 */
float *dao_test_ao_of_depth(const struct dao_camera *cam, const float *depth, int algorithm,
			    int thickness_mode, float thickness);

/*
 * Opens the Kinect recording ../shared/data/oni/3DJ_test.oni: its reader,
 * the depth stream's index and info, and a camera of its field of view.
 * Returns 0, DAO_TEST_SKIP when the file is absent, or 1 after printing
 * why it failed.
 */
int dao_test_open_kinect(struct dao_oni_reader **rd, int *stream,
			 const struct dao_oni_stream_info **si, struct dao_camera *cam);

#endif
