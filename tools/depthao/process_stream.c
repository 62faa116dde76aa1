/* SPDX-License-Identifier: MIT */
/*
 * depthao process on a recording or device: frames come from a source
 * plugin (the built-in .oni reader, OpenNI2, ...), outputs are numbered by
 * the frame's position in the recording (live: by arrival).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "common/cli_plugins.h"
#include "commands.h"
#include "file_list.h"
#include "process.h"
#include "progress.h"

/* Live sources: how long a read may wait, and how many empty waits end the run. */
#define READ_TIMEOUT_MS 2000
#define MAX_EMPTY_READS 5

/* A rosbag2 directory: one with a metadata.yaml (the db3 source reads it), maybe with ?options. */
static int is_rosbag2_dir(const char *input)
{
	const char *q = strrchr(input, '?');
	char *dir = strndup(input, q ? (size_t)(q - input) : strlen(input));
	char *meta = dir ? path_join(dir, "metadata.yaml") : NULL;
	struct stat st;
	int yes = meta && stat(meta, &st) == 0 && S_ISREG(st.st_mode);
	free(meta);
	free(dir);
	return yes;
}

int process_input_is_stream(const char *input)
{
	size_t n = strlen(input);
	return (n > 4 && (!strcasecmp(input + n - 4, ".oni") || !strcasecmp(input + n - 4, ".bag") ||
			  !strcasecmp(input + n - 4, ".db3"))) ||
	       strstr(input, ".bag?") || (n > 5 && !strcasecmp(input + n - 5, ".mcap")) ||
	       strstr(input, ".mcap?") || strstr(input, ".db3?") || dao_uri_prefix_len(input) > 0 ||
	       is_rosbag2_dir(input);
}

const char *process_input_path(const char *input)
{
	size_t n = dao_uri_prefix_len(input);
	return input + (n ? n + 1 : 0);
}

static char *numbered(const char *dir, uint64_t index, const char *ext)
{
	char name[40];
	if (!dir)
		return NULL;
	snprintf(name, sizeof name, "%06llu.%s", (unsigned long long)index, ext);
	return path_join(dir, name);
}

/* The frames a run writes: what is left of a recording after --start, at most --frames. */
static uint64_t frames_to_write(const struct process_options *o, const struct dao_source_info *si)
{
	if (si->frame_count < 0)
		return o->max_frames;
	uint64_t left = (uint64_t)si->frame_count > o->start ? (uint64_t)si->frame_count - o->start
							      : 0;
	return o->max_frames && o->max_frames < left ? o->max_frames : left;
}

static int run(const struct process_options *o, struct dao_source *src,
	       const struct dao_source_info *si, struct run_state *st)
{
	struct dao_error err;
	uint64_t total = frames_to_write(o, si);
	struct progress bar;
	progress_begin(&bar, (size_t)total, o->quiet);
	int status = 0, empty = 0;
	uint64_t done = 0;
	while (!status && done < total) {
		struct dao_source_frame f;
		int r = dao_source_read(src, &f, READ_TIMEOUT_MS, &err);
		if (r == DAO_SOURCE_EOS)
			break;
		if (r == -EAGAIN) {
			if (++empty < MAX_EMPTY_READS)
				continue;
			fprintf(stderr, "depthao: no frame from '%s' for %d s; giving up\n", o->input,
				READ_TIMEOUT_MS * MAX_EMPTY_READS / 1000);
			status = 1;
			break;
		}
		if (r < 0 && !si->live && r != -ENODEV && r != -ENOMEM) {
			/* a recording's frame that cannot be decoded (corrupt depth, a damaged
			 * JPEG colour frame): the source skips it; warned per frame, counted,
			 * and the run ends with status 1 */
			fprintf(stderr, "depthao: warning: a frame is skipped: %s\n", err.message);
			st->skipped++;
			done++;
			continue;
		}
		if (r < 0) {
			process_print_error(&err);
			status = 1;
			break;
		}
		empty = 0;
		uint64_t index = si->live ? done : f.index;
		char *ao = numbered(o->ao_out, index, "png"), *sh = numbered(o->shaded_out, index, "png");
		char *ov = numbered(o->overlay_out, index, "png");
		char *dp = numbered(o->depth_out, index, "png");
		char *pc = process_cloud_is_file(o) ? strdup(o->cloud_out)
						    : numbered(o->cloud_out, index, "ply");
		if ((o->ao_out && !ao) || (o->shaded_out && !sh) || (o->overlay_out && !ov) ||
		    (o->cloud_out && !pc) || (o->depth_out && !dp)) {
			fprintf(stderr, "depthao: out of memory\n");
			status = 1;
		} else {
			struct process_paths paths = { ao, sh, ov, pc, dp };
			if (process_wants_source_poses(o))
				status = process_source_pose(o, st, src, &f);
			if (!status)
				status = process_depth(o, st, &f.depth, &f.color, &paths,
						       o->frame_index + index);
		}
		free(ao);
		free(sh);
		free(ov);
		free(pc);
		free(dp);
		dao_source_release(src, &f);
		done++;
		progress_update(&bar, (size_t)done, st->ms_total / (double)(st->frames ? st->frames : 1));
	}
	progress_end(&bar);
	return status;
}

/*
 * The built-in sources first (a recording then costs no plugin modules; OpenCV
 * and OpenNI2 pull in tens of megabytes), the modules only when no built-in
 * takes it.
 */
int process_open_source(const struct process_options *o, struct dao_plugins **plugins,
			struct dao_source **src)
{
	struct dao_error err;
	struct dao_source_options so = {
		.size = sizeof(struct dao_source_options),
		.playback = o->realtime ? DAO_PLAYBACK_REALTIME : DAO_PLAYBACK_MANUAL,
		.start_frame = o->start,
		.want_color = o->overlay_out != NULL,
		.depth_unit = (float)o->depth_unit,
	};
	char *uri = process_source_uri(o);
	if (!uri) {
		fprintf(stderr, "depthao: out of memory\n");
		return 1;
	}
	if (dao_plugins_load(plugins, "", &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		free(uri);
		return 1;
	}
	int r = dao_source_open_limited(*plugins, uri, &so, o->max_pixels, src, &err);
	if (r == -ENOENT && !strncmp(err.message, "no source", 9)) {
		/* no built-in source for this URI ("no source plugin ...", "no source
		 * recognises ..."; not a missing file) */
		dao_plugins_free(*plugins);
		*plugins = NULL;
		if (cli_plugins_load(plugins, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			free(uri);
			return 1;
		}
		r = dao_source_open_limited(*plugins, uri, &so, o->max_pixels, src, &err);
	}
	free(uri);
	if (r) {
		process_print_error(&err);
		return 1;
	}
	return 0;
}

/* Does the source give what the options ask (frame limits, colour)?  0 or the exit status. */
static int check_source(const struct process_options *o, const struct dao_source_info *si)
{
	struct dao_error err;
	if (si->live && !o->max_frames) {
		usage_error("process", "'%s' is a live source; give --frames N", o->input);
		return 2;
	}
	if (si->live && o->start) {
		usage_error("process", "--start applies to recordings, '%s' is a live source",
			    o->input);
		return 2;
	}
	if (!o->quiet)
		fprintf(stderr, "depthao: %s\n", si->description);
	if (si->warning[0])
		fprintf(stderr, "depthao: warning: %s\n", si->warning);
	if (o->overlay_out && !si->has_color) {
		fprintf(stderr, "depthao: --overlay-out needs colour, and '%s' delivers depth only "
			"(%s): give a recording or device with a colour stream, or leave out "
			"--overlay-out\n", o->input, si->description);
		return 1;
	}
	if (o->overlay_out && dao_overlay_check(si->color_width, si->color_height, si->width,
						si->height, &err) < 0) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	if (o->overlay_out && !si->registered && !o->quiet)
		fprintf(stderr, "depthao: warning: the depth is not registered to the colour camera "
			"(or the source cannot tell): the overlay is offset by the parallax between "
			"the two cameras\n");
	return process_check_cloud_frames(o, frames_to_write(o, si), 1);
}

/* The camera, the output directories, the context and frames; the source started. */
static int prepare_run(const struct process_options *o, struct dao_source *src,
		       const struct dao_source_info *si, struct run_state *st)
{
	struct dao_error err;
	struct dao_camera cam;
	int status;
	if ((status = process_resolve_camera(o, si->width, si->height, si, &cam)))
		return status;
	if ((o->ao_out && process_ensure_dir(o->ao_out)) ||
	    (o->shaded_out && process_ensure_dir(o->shaded_out)) ||
	    (o->overlay_out && process_ensure_dir(o->overlay_out)) ||
	    (o->depth_out && process_ensure_dir(o->depth_out)) ||
	    (o->cloud_out && !process_cloud_is_file(o) && process_ensure_dir(o->cloud_out)))
		return 1;
	if (dao_context_create(&st->ctx, &cam, &o->params, &err) ||
	    dao_frame_alloc(&st->overlay, DAO_PIXFMT_RGB24, si->width, si->height, &err) ||
	    dao_frame_alloc(&st->ao, DAO_PIXFMT_GRAY16, si->width, si->height, &err) ||
	    dao_frame_alloc(&st->rgb, DAO_PIXFMT_RGB24, si->width, si->height, &err) ||
	    process_alloc_depth_outputs(o, st, si->width, si->height, &err) ||
	    dao_source_start(src, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	int status2 = process_mcap_open(o, st, &cam, si->fps);
	return status2 ? status2 : process_pose_open(o, st);
}

void process_print_summary(const struct process_options *o, const struct run_state *st)
{
	const char *outs[] = { o->ao_out, o->shaded_out, o->overlay_out, o->cloud_out,
			       o->mcap_out, o->depth_out, o->pose_out };
	int n = 0;
	fprintf(stderr, "depthao: %zu frame%s, %.1f ms/frame (%s), wrote", st->frames,
		st->frames == 1 ? "" : "s", st->ms_total / (double)st->frames,
		o->params.algorithm == DAO_ALGORITHM_NONE ? "depth only" : "AO");
	for (size_t k = 0; k < sizeof outs / sizeof outs[0]; k++)
		if (outs[k])
			fprintf(stderr, "%s%s", n++ ? " and " : " ", outs[k]);
	fputc('\n', stderr);
}

int process_stream(const struct process_options *o)
{
	struct dao_plugins *plugins = NULL;
	struct dao_source *src = NULL;
	struct run_state st = {0};
	struct dao_source_info si;
	int status = process_open_source(o, &plugins, &src);
	if (!status) {
		dao_source_get_info(src, &si);
		status = check_source(o, &si);
	}
	if (!status)
		status = prepare_run(o, src, &si, &st);
	if (!status)
		status = run(o, src, &si, &st);
	if (!status && st.skipped) {
		fprintf(stderr, "depthao: %zu frame%s of '%s' could not be read and %s skipped "
			"(the warnings above say why); the other %zu were written\n", st.skipped,
			st.skipped == 1 ? "" : "s", o->input, st.skipped == 1 ? "was" : "were",
			st.frames);
		status = 1;
	}
	if (!status && st.frames == 0) {
		fprintf(stderr, "depthao: '%s' delivered no frames\n", o->input);
		status = 1;
	}
	if (!status)
		process_source_poses_report(o, &st);
	if (!status && !o->quiet)
		process_print_summary(o, &st);
	status = process_mcap_close(&st, status);
	status = process_pose_close(o, &st, status);
	dao_source_close(src);
	process_free_outputs(&st);
	dao_context_destroy(st.ctx);
	dao_plugins_free(plugins);
	return status;
}
