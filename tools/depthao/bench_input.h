/* SPDX-License-Identifier: MIT */
/*
 * depthao bench --input: the user's depth frames, read into memory once
 * through the sources `depthao process` opens, with the camera it would use.
 */
#ifndef DAO_TOOLS_BENCH_INPUT_H
#define DAO_TOOLS_BENCH_INPUT_H

#include <stdint.h>

#include <depthao/depthao.h>

#include "process.h"

#define BENCH_INPUT_DEFAULT_FRAMES 30
#define BENCH_INPUT_MAX_FRAMES 10000
/* the most depth bench holds in memory: 2 GiB */
#define BENCH_INPUT_MAX_BYTES (2ull << 30)

/* --input and what goes with it. */
struct bench_input_options {
	/* input, cmd, the camera options, depth_unit, max_pixels: as `process` takes them */
	struct process_options po;
	uint32_t frames; /* --input-frames */
	int given;       /* bit k: option k of bench_input_names was given */
};

/* The options' long names: "input" first. */
extern const char *const bench_input_names[];
#define BENCH_INPUT_NOPTIONS 7

/* The frames to time, in memory. */
struct bench_input {
	struct dao_camera cam;
	struct dao_frame *frames; /* n frames of cam's size, one format, in the source's order */
	uint32_t n;
	/* timed as a stream (the frame index increasing, the stream defaults): a
	 * recording, a device or a directory; not one PNG file */
	int stream;
	char description[160]; /* the source's */
	void *data;             /* the pixels of all frames */
};

/* Defaults (no input, 30 frames, depth unit 0.001). */
void bench_input_options_init(struct bench_input_options *io);
/* Option k of bench_input_names with its value: 0 or a usage error's exit status. */
int bench_input_option(struct bench_input_options *io, int k, const char *value);
/* After the command line: the options that go with --input need it, and --size does not
 * go with it.  0 or a usage error's exit status. */
int bench_input_check(struct bench_input_options *io, int size_given,
		      const struct dao_params *params);

/* Reads the frames: 0, or the exit status (1, 2 for a usage error), the message printed. */
int bench_input_load(const struct bench_input_options *io, struct bench_input *in);
void bench_input_free(struct bench_input *in);

#endif
