/* SPDX-License-Identifier: MIT */
/*
 * depthao bench --input: the frames of a 16-bit depth PNG, a directory of
 * them, a recording or a source URI, read once into one block of memory
 * before anything is timed (the timed loop then reads no file and allocates
 * nothing), with the camera `depthao process` would take for them.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "bench_input.h"
#include "commands.h"
#include "common/pixel_limit.h"
#include "file_list.h"
#include "process.h"

/* Live sources: how long a read may wait, and how many empty waits end the reading. */
#define READ_TIMEOUT_MS 2000
#define MAX_EMPTY_READS 5

enum { IN_INPUT, IN_FRAMES, IN_INTRINSICS, IN_FOV, IN_INTRINSICS_FILE, IN_DEPTH_UNIT,
       IN_MAX_PIXELS, IN_COUNT };
_Static_assert(IN_COUNT == BENCH_INPUT_NOPTIONS, "a name per input option");

const char *const bench_input_names[BENCH_INPUT_NOPTIONS] = {
	"input", "input-frames", "intrinsics", "fov", "intrinsics-file", "depth-unit", "max-pixels"
};

void bench_input_options_init(struct bench_input_options *io)
{
	*io = (struct bench_input_options){ .frames = BENCH_INPUT_DEFAULT_FRAMES };
	io->po.cmd = "bench";
	io->po.depth_unit = 0.001;
}

int bench_input_option(struct bench_input_options *io, int k, const char *value)
{
	char *end;
	io->given |= 1 << k;
	switch (k) {
	case IN_INPUT:
		io->po.input = value;
		return *value ? 0 : usage_error("bench", "--input needs a file, directory or URI");
	case IN_FRAMES: {
		errno = 0;
		unsigned long n = strtoul(value, &end, 10);
		if (*end || end == value || errno || value[0] == '-' || n < 1 ||
		    n > BENCH_INPUT_MAX_FRAMES)
			return usage_error("bench", "--input-frames needs a count from 1 to %d",
					   BENCH_INPUT_MAX_FRAMES);
		io->frames = (uint32_t)n;
		return 0;
	}
	case IN_INTRINSICS:
		io->po.intrinsics = value;
		return 0;
	case IN_FOV:
		io->po.fov = value;
		return 0;
	case IN_INTRINSICS_FILE:
		io->po.intrinsics_file = value;
		return 0;
	case IN_DEPTH_UNIT:
		io->po.depth_unit = strtod(value, &end);
		if (*end || end == value || !(io->po.depth_unit > 0 && io->po.depth_unit <= 1))
			return usage_error("bench", "--depth-unit '%s' must be a number in (0, 1] "
					   "metres per count", value);
		return 0;
	case IN_MAX_PIXELS:
		if (pixel_limit_parse(value, &io->po.max_pixels))
			return usage_error("bench", "--max-pixels '%s' must be a pixel count or WxH, "
					   "at most 16384x16384", value);
		return 0;
	}
	return usage_error("bench", "internal: input option %d", k);
}

int bench_input_check(struct bench_input_options *io, int size_given,
		      const struct dao_params *params)
{
	if (!io->po.input) {
		int k = 1;
		while (k < BENCH_INPUT_NOPTIONS && !(io->given >> k & 1))
			k++;
		return k < BENCH_INPUT_NOPTIONS
			       ? usage_error("bench", "--%s goes with --input PATH (the synthetic "
					     "frame has its own camera and size)", bench_input_names[k])
			       : 0;
	}
	if (size_given)
		return usage_error("bench", "--size is the synthetic frame's; --input '%s' is timed "
				   "at its own size: leave out --size", io->po.input);
	if (params->depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE ||
	    params->depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE_ICP)
		return usage_error("bench", "--depth-temporal-motion source and source+icp take the "
				   "camera's poses from a recording, and bench does not read them: "
				   "time icp or off");
	return process_camera_options(&io->po);
}

/* One PNG file (not a directory, not a recording): timed as one frame, not as a stream. */
static int is_one_png(const char *input)
{
	const char *path = process_input_path(input);
	/* the name without its options (images:x.png?unit=0.0002) */
	size_t n = dao_uri_path_len(path, NULL);
	if (dao_uri_prefix_len(input) > 0 && strncmp(input, "images:", 7))
		return 0;
	if (n <= 4 || strncasecmp(path + n - 4, ".png", 4))
		return 0;
	char *name = strndup(path, n);
	const int dir = name ? path_is_dir(name) : -1;
	free(name);
	return dir != 1;
}

static size_t frame_bytes(const struct dao_source_info *si)
{
	return (size_t)si->width * si->height * dao_pixfmt_bytes_per_pixel(si->format);
}

/* The frames to read: --input-frames, or fewer if the recording has fewer; 0 or the exit
 * status when there are none or they would take more memory than bench holds. */
static int frames_to_read(const struct bench_input_options *io, const struct dao_source_info *si,
			  uint32_t *n)
{
	const char *in = io->po.input;
	uint64_t want = io->frames;
	if (si->frame_count >= 0 && (uint64_t)si->frame_count < want)
		want = (uint64_t)si->frame_count;
	if (want == 0) {
		fprintf(stderr, "depthao: '%s' has no frames: give a recording or directory with "
			"depth frames\n", in);
		return 1;
	}
	if (si->format != DAO_PIXFMT_DEPTH16 && si->format != DAO_PIXFMT_DEPTH_F32) {
		fprintf(stderr, "depthao: '%s' delivers %s images, not depth: give its depth "
			"topic or stream (?topic=...) or 16-bit depth PNGs\n", in,
			dao_pixfmt_name(si->format));
		return 1;
	}
	const double each = (double)frame_bytes(si);
	if (want * each > (double)BENCH_INPUT_MAX_BYTES) {
		uint64_t fit = BENCH_INPUT_MAX_BYTES / frame_bytes(si);
		fprintf(stderr, "depthao: %llu frames of %ux%u %s take %.0f MiB, more than "
			"bench holds in memory (%.0f MiB): give --input-frames %llu or fewer\n",
			(unsigned long long)want, si->width, si->height, dao_pixfmt_name(si->format),
			ceil(want * each / (1u << 20)), (double)BENCH_INPUT_MAX_BYTES / (1u << 20),
			(unsigned long long)fit);
		return 1;
	}
	*n = (uint32_t)want;
	return 0;
}

/* Frame k, as read, into its place in in->data; 0 or the exit status if it is not of the
 * first frame's size and format. */
static int keep_frame(const struct bench_input_options *io, const struct dao_source_info *si,
		      const struct dao_frame *f, uint32_t k, struct bench_input *in)
{
	if (f->width != si->width || f->height != si->height || f->format != si->format) {
		fprintf(stderr, "depthao: frame %u of '%s' is %ux%u %s, but the input's frames are "
			"%ux%u %s: bench times frames of one size and format", k, io->po.input,
			f->width, f->height, dao_pixfmt_name(f->format), si->width, si->height,
			dao_pixfmt_name(si->format));
		if (k)
			fprintf(stderr, " (--input-frames %u times the frame%s before it)", k,
				k == 1 ? "" : "s");
		fputc('\n', stderr);
		return 1;
	}
	const size_t row = (size_t)f->width * dao_pixfmt_bytes_per_pixel(f->format);
	uint8_t *dst = (uint8_t *)in->data + (size_t)k * frame_bytes(si);
	for (uint32_t y = 0; y < f->height; y++)
		memcpy(dst + y * row, (const uint8_t *)f->data + (size_t)y * (size_t)f->stride, row);
	in->frames[k] = (struct dao_frame){ .format = f->format, .width = f->width,
					    .height = f->height, .stride = (int32_t)row,
					    .data = dst, .depth_unit = f->depth_unit,
					    .timestamp_ns = f->timestamp_ns,
					    .sequence = f->sequence, .size = DAO_FRAME_SIZE };
	return 0;
}

/* Up to `want` frames of the started source into `in`: 0 or the exit status. */
static int read_frames(const struct bench_input_options *io, struct dao_source *src,
		       const struct dao_source_info *si, uint32_t want, struct bench_input *in)
{
	const char *input = io->po.input;
	struct dao_error err;
	int empty = 0;
	while (in->n < want) {
		struct dao_source_frame f;
		int r = dao_source_read(src, &f, READ_TIMEOUT_MS, &err);
		if (r == DAO_SOURCE_EOS)
			break;
		if (r == -EAGAIN && ++empty < MAX_EMPTY_READS)
			continue;
		if (r == -EAGAIN) {
			fprintf(stderr, "depthao: no frame from '%s' for %d s: check that the "
				"device streams, or time a recording of it\n", input,
				READ_TIMEOUT_MS * MAX_EMPTY_READS / 1000);
			return 1;
		}
		if (r < 0) {
			fprintf(stderr, "depthao: frame %u of '%s' cannot be read: %s", in->n, input,
				err.message);
			if (in->n)
				fprintf(stderr, " (--input-frames %u times the frame%s before it)",
					in->n, in->n == 1 ? "" : "s");
			fputc('\n', stderr);
			return 1;
		}
		empty = 0;
		r = keep_frame(io, si, &f.depth, in->n, in);
		dao_source_release(src, &f);
		if (r)
			return r;
		in->n++;
	}
	if (in->n == 0) {
		fprintf(stderr, "depthao: '%s' delivered no frames: give a recording or "
			"directory with depth frames\n", input);
		return 1;
	}
	return 0;
}

/* The camera, the frames' memory and the frames of an open source: 0 or the exit status. */
static int load_from(const struct bench_input_options *io, struct dao_source *src,
		     struct bench_input *in)
{
	struct dao_source_info si = { .size = sizeof si };
	struct dao_error err;
	uint32_t want = 0;
	dao_source_get_info(src, &si);
	int status = frames_to_read(io, &si, &want);
	if (!status)
		status = process_resolve_camera(&io->po, si.width, si.height, &si, &in->cam);
	if (status)
		return status;
	snprintf(in->description, sizeof in->description, "%s", si.description);
	in->data = malloc((size_t)want * frame_bytes(&si));
	in->frames = calloc(want, sizeof *in->frames);
	if (!in->data || !in->frames) {
		fprintf(stderr, "depthao: out of memory for %u frames of %ux%u: give a smaller "
			"--input-frames\n", want, si.width, si.height);
		return 1;
	}
	if (dao_source_start(src, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	return read_frames(io, src, &si, want, in);
}

int bench_input_load(const struct bench_input_options *io, struct bench_input *in)
{
	struct dao_plugins *plugins = NULL;
	struct dao_source *src = NULL;
	const char *input = io->po.input;
	*in = (struct bench_input){ .stream = !is_one_png(input) };
	/* a path (no NAME: prefix, no ?options) that is not there: said as such, not as "no
	 * source recognises it" */
	int there = dao_uri_prefix_len(input) > 0 || strchr(input, '?') ? 1 : path_is_dir(input);
	if (there < 0) {
		fprintf(stderr, "depthao: cannot read --input '%s': %s\n", input, strerror(-there));
		return 1;
	}
	int status = process_open_source(&io->po, &plugins, &src);
	if (!status)
		status = load_from(io, src, in);
	dao_source_close(src);
	dao_plugins_free(plugins);
	if (status)
		bench_input_free(in);
	return status;
}

void bench_input_free(struct bench_input *in)
{
	free(in->frames);
	free(in->data);
	in->frames = NULL;
	in->data = NULL;
	in->n = 0;
}
