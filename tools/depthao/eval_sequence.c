/* SPDX-License-Identifier: MIT */
/*
 * depthao eval --sequence PATH (issue #37): runs a depth sequence through the
 * library with the temporal filters off, with the depth filter on, and with
 * the depth filter and the AO history on, and prints per frame the MAE
 * against the truth and the trail MAE, then the means and the flicker
 * (tools/synth/sequence_metrics.h says what each measures).
 *
 * PATH is what `depthao synth --trajectory` (or --frames) writes: depth/
 * (PNGs + camera.json), ao_gt/, depth_gt/ and poses.txt, each but depth/
 * optional; or a directory of depth PNGs with its camera file; or an .oni
 * recording.  Without ao_gt/ only flicker and change are measured.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "cli_params.h"
#include "commands.h"
#include "common/camera_file.h"
#include "eval_sequence.h"
#include "file_list.h"
#include "synth/sequence_metrics.h"
#include "synth/trajectory.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define NCOLS 5
#define ON_DEPTH_TEMPORAL 0.8f   /* the streams' default (dao_params_stream_defaults) */
#define ON_AO_TEMPORAL 0.8f      /* the AO history's documented setting ("settles in ~5 frames") */
#define MOVE_EPS 1e-4            /* m and rad: a pose this close to frame 0's is still */
#define WORSE_EPS 1e-5           /* a frame is worse than off by more than rounding */

static const char *const col_names[NCOLS] = { "off", "depth", "depth+AO", "depth+ICP",
					       "depth+AO+ICP" };
/* the columns' settings: the depth filter, the AO history, depth-temporal-motion=icp */
static const int col_depth[NCOLS] = { 0, 1, 1, 1, 1 };
static const int col_ao[NCOLS] = { 0, 0, 1, 0, 1 };
static const int col_icp[NCOLS] = { 0, 0, 0, 1, 1 };
/* the picture's panels: the truth, then these columns */
#define PIC_COLS 3
static const int pic_col[PIC_COLS] = { 0, 2, 4 };

struct seq_options {
	const char *path, *camera;
	float depth_unit;
	long max_frames;
	const char *picture;
	long picture_frame; /* -1: the last */
	long settle;        /* --settle K: flicker and change also from frame K (0: not) */
	enum dao_quality quality;
	char *overrides[64];
	int n_override;
};

struct seq_input {
	char *depth_dir, *gt_dir, *truth_dir, *pose_path;
	struct file_list depth, gt, truth;
	int have_gt, have_truth, have_poses, camera_moves;
	struct dao_oni_reader *oni;
	uint32_t stream;
	struct dao_camera cam;
	long frames;
	struct synth_pose_list poses;
};

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao eval --sequence PATH [options] [parameter options]\n"
		"\n"
		"Runs a depth sequence through the library five times: temporal filters off\n"
		"(--depth-temporal 0 --temporal 0), the depth filter on (--depth-temporal 0.8),\n"
		"the depth filter and the AO history on (--depth-temporal 0.8 --temporal 0.8), and\n"
		"those two again with the histories following the camera's motion\n"
		"(--depth-temporal-motion icp: depth+ICP, depth+AO+ICP), and prints per frame the MAE against the truth and the trail MAE (in the band that a\n"
		"depth discontinuity swept in the last %d frames), then the means, the frames where\n"
		"a filter is worse than off, the flicker (temporal std of the AO on static surfaces:\n"
		"per surface point, followed with depth_gt/ and poses.txt, else per pixel) and the\n"
		"mean frame-to-frame AO change.\n"
		"\n"
		"PATH: a sequence of 'depthao synth --trajectory' (depth/, ao_gt/, depth_gt/,\n"
		"poses.txt; all but depth/ optional), a directory of 16-bit depth PNGs with a\n"
		"camera.json, or an .oni recording (no truth: flicker and change only).\n"
		"\n"
		"  --camera FILE     the camera file (default: camera.json beside the depth PNGs)\n"
		"  --depth-unit M    metres per PNG count (default 0.001)\n"
		"  --frames N        at most N frames\n"
		"  --quality NAME    the preset (default medium); parameter options override it in\n"
		"                    all five runs, except the three temporal settings\n"
		"  --picture PATH    PNG of one frame: the truth, off, depth+AO and depth+AO+ICP;\n"
		"                    above the AO, below the input depth and each one's error\n"
		"  --picture-frame K that frame (default: the last)\n"
		"  --settle K        also the flicker and change from frame K on (K + 2 frames\n"
		"                    at least), once the histories have settled (frame 0 has\n"
		"                    none to average with)\n"
		"  --help            this text\n",
		SYNTH_TRAIL_FRAMES);
}

static int parse_value(struct seq_options *o, const char *a, const char *v)
{
	char *end;
	errno = 0;
	if (strcmp(a, "--sequence") == 0) {
		o->path = v;
	} else if (strcmp(a, "--camera") == 0) {
		o->camera = v;
	} else if (strcmp(a, "--depth-unit") == 0) {
		o->depth_unit = strtof(v, &end);
		if (*end || !*v || !(o->depth_unit > 0.0f && o->depth_unit <= 1.0f))
			return usage_error("eval", "--depth-unit '%s' must be a number in (0, 1] metres", v);
	} else if (strcmp(a, "--picture") == 0) {
		o->picture = v;
	} else if (strcmp(a, "--picture-frame") == 0) {
		o->picture_frame = strtol(v, &end, 10);
		if (*end || !*v || errno || o->picture_frame < 0 || o->picture_frame > 100000)
			return usage_error("eval", "--picture-frame '%s' must be an integer in 0..100000",
					   v);
	} else if (strcmp(a, "--settle") == 0) {
		o->settle = strtol(v, &end, 10);
		if (*end || !*v || errno || o->settle < 1 || o->settle > 100000)
			return usage_error("eval", "--settle '%s' must be an integer in 1..100000", v);
	} else if (strcmp(a, "--frames") == 0) {
		o->max_frames = strtol(v, &end, 10);
		if (*end || !*v || errno || o->max_frames < 1 || o->max_frames > 100000)
			return usage_error("eval", "--frames '%s' must be an integer in 1..100000", v);
	} else {
		struct dao_error err;
		if (dao_quality_parse(v, &o->quality, &err))
			return usage_error("eval", "%s", err.message);
	}
	return 0;
}

static int parse_args(int argc, char **argv, struct seq_options *o)
{
	*o = (struct seq_options){ .depth_unit = 0.001f, .quality = DAO_QUALITY_DEFAULT,
				   .picture_frame = -1 };
	static const char *const valued[] = { "--sequence", "--camera", "--depth-unit", "--frames",
					      "--quality", "--picture", "--picture-frame", "--settle" };
	const size_t nvalued = sizeof valued / sizeof valued[0];
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		size_t k;
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			usage(stdout);
			exit(0);
		}
		for (k = 0; k < nvalued && strcmp(a, valued[k]) != 0; k++)
			;
		if (k < nvalued) {
			if (i + 1 >= argc)
				return usage_error("eval", "%s needs a value", a);
			int r = parse_value(o, a, argv[++i]);
			if (r)
				return r;
			continue;
		}
		struct dao_params scratch;
		dao_params_init(&scratch, DAO_QUALITY_DEFAULT);
		char msg[DAO_ERROR_MESSAGE_MAX];
		int j = i;
		int r = cli_apply_param_option(&scratch, argc, argv, &j, msg, sizeof msg);
		if (r < 0)
			return usage_error("eval", "%s", msg);
		if (r == 0)
			return usage_error("eval", "--sequence: unknown option '%s'", a);
		for (int k2 = i; k2 <= j && o->n_override < 64; k2++)
			o->overrides[o->n_override++] = argv[k2];
		i = j;
	}
	if (!o->path)
		return usage_error("eval", "--sequence needs a path");
	return 0;
}

/* The parameters of column `col`: the preset, the overrides, the column's temporal settings. */
static int column_params(const struct seq_options *o, int col, struct dao_params *p)
{
	dao_params_init(p, o->quality);
	dao_params_stream_defaults(p);
	char *args[66] = { "eval" };
	for (int k = 0; k < o->n_override; k++)
		args[k + 1] = o->overrides[k];
	char msg[DAO_ERROR_MESSAGE_MAX];
	for (int i = 1; i <= o->n_override; i++)
		if (cli_apply_param_option(p, o->n_override + 1, args, &i, msg, sizeof msg) < 0) {
			fprintf(stderr, "depthao: %s\n", msg);
			return 1;
		}
	p->depth_temporal = col_depth[col] ? ON_DEPTH_TEMPORAL : 0.0f;
	p->temporal = col_ao[col] ? ON_AO_TEMPORAL : 0.0f;
	p->depth_temporal_motion = col_icp[col] ? DAO_DEPTH_MOTION_ICP : DAO_DEPTH_MOTION_OFF;
	struct dao_error err;
	if (dao_params_validate(p, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	return 0;
}

static int ends_with(const char *s, const char *tail)
{
	size_t n = strlen(s), m = strlen(tail);
	return n >= m && strcmp(s + n - m, tail) == 0;
}

/* An optional directory of PNGs beside depth/: 1 if present with `frames` files, 0 if absent. */
static int optional_dir(const char *base, const char *name, char **dir, struct file_list *l,
			long frames)
{
	*dir = path_join(base, name);
	if (!*dir || path_is_dir(*dir) != 1 || file_list_pngs(*dir, l))
		return 0;
	if ((long)l->count < frames) {
		fprintf(stderr, "depthao: warning: %s has %zu frames, fewer than depth/'s %ld: not used\n",
			*dir, l->count, frames);
		return 0;
	}
	return 1;
}

/* 1 if any pose differs from the first by more than MOVE_EPS. */
static int poses_move(const struct synth_pose_list *l)
{
	for (size_t k = 1; k < l->count; k++) {
		double d = 0.0;
		for (int j = 0; j < 3; j++)
			d = fmax(d, fabs(l->pose[k].t[j] - l->pose[0].t[j]));
		if (d > MOVE_EPS || synth_rotation_angle(l->pose[0].R, l->pose[k].R) > MOVE_EPS)
			return 1;
	}
	return 0;
}

/* PATH/depth/ of a synth sequence, or PATH itself as the PNG directory. */
static int open_png_dirs(const struct seq_options *o, struct seq_input *in)
{
	char msg[512];
	char *sub = path_join(o->path, "depth");
	int layout = sub && path_is_dir(sub) == 1;
	in->depth_dir = layout ? sub : strdup(o->path);
	if (!layout)
		free(sub);
	if (!in->depth_dir)
		return 1;
	int r = file_list_pngs(in->depth_dir, &in->depth);
	if (r || in->depth.count == 0) {
		fprintf(stderr, "depthao: %s: %s\n", in->depth_dir,
			r ? strerror(-r) : "no .png depth frames in it");
		return 1;
	}
	in->frames = (long)in->depth.count;
	char *cam = o->camera ? strdup(o->camera) : path_join(in->depth_dir, "camera.json");
	r = !cam || camera_file_read(cam, &in->cam, msg, sizeof msg);
	if (r)
		fprintf(stderr, "depthao: %s (give the intrinsics with --camera FILE)\n",
			cam ? msg : "out of memory");
	free(cam);
	if (r || !layout)
		return r;
	in->have_gt = optional_dir(o->path, "ao_gt", &in->gt_dir, &in->gt, in->frames);
	in->have_truth = optional_dir(o->path, "depth_gt", &in->truth_dir, &in->truth, in->frames);
	in->pose_path = path_join(o->path, "poses.txt");
	if (in->pose_path && path_is_dir(in->pose_path) == 0) {
		struct dao_error err;
		if (synth_poses_read(in->pose_path, &in->poses, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		in->have_poses = 1;
		in->camera_moves = poses_move(&in->poses);
	}
	return 0;
}

static int open_oni(const struct seq_options *o, struct seq_input *in)
{
	struct dao_error err;
	int s;
	if (dao_oni_reader_open(o->path, &in->oni, &err) ||
	    (s = dao_oni_reader_depth_stream(in->oni, &err)) < 0) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	in->stream = (uint32_t)s;
	const struct dao_oni_stream_info *si = dao_oni_reader_stream(in->oni, in->stream);
	in->frames = si->frame_count;
	if (o->camera) {
		char msg[512];
		if (camera_file_read(o->camera, &in->cam, msg, sizeof msg)) {
			fprintf(stderr, "depthao: %s\n", msg);
			return 1;
		}
	} else if (!si->has_fov || dao_camera_from_fov(&in->cam, si->width, si->height, si->hfov,
							 si->vfov, &err)) {
		fprintf(stderr, "depthao: %s: no usable field of view; give --camera FILE\n", o->path);
		return 1;
	}
	return 0;
}

static void close_input(struct seq_input *in)
{
	file_list_free(&in->depth);
	file_list_free(&in->gt);
	file_list_free(&in->truth);
	free(in->depth_dir);
	free(in->gt_dir);
	free(in->truth_dir);
	free(in->pose_path);
	synth_pose_list_free(&in->poses);
	dao_oni_reader_close(in->oni);
}

/* A 16-bit PNG of the sequence as floats: depth (x unit) or visibility (/ 65535). */
static int read_png_float(const char *dir, const char *name, const struct dao_camera *cam,
			  double scale, float *out, struct dao_error *err)
{
	char *p = path_join(dir, name);
	struct dao_frame f = { 0 };
	int r = !p ? dao_error_set(err, -ENOMEM, "out of memory") : dao_png_read(p, &f, err);
	if (!r && (f.width != cam->width || f.height != cam->height ||
		   (f.format != DAO_PIXFMT_GRAY16 && f.format != DAO_PIXFMT_DEPTH16)))
		r = dao_error_set(err, -EINVAL, "%s: not a 16-bit %ux%u image like the depth frames",
				  p, cam->width, cam->height);
	for (uint32_t y = 0; !r && y < f.height; y++) {
		const uint16_t *row = (const uint16_t *)((const uint8_t *)f.data + (size_t)y * f.stride);
		for (uint32_t x = 0; x < f.width; x++)
			out[(size_t)y * f.width + x] = (float)(row[x] * scale);
	}
	dao_frame_free(&f);
	free(p);
	return r;
}

struct seq_run {
	const struct seq_options *o;
	struct seq_input in;
	struct dao_context *ctx[NCOLS];
	struct synth_seq_masks masks;
	struct synth_seq_column cols[NCOLS];
	struct synth_seq_column settled[NCOLS]; /* --settle: the same from frame K on */
	struct synth_seq_track track;
	int tracking;                   /* true depth and poses: flicker per surface point */
	struct synth_seq_frame (*res)[NCOLS];
	uint16_t *depth16;
	float *depth, *gt, *truth, *ao;
	long motion[NCOLS][4]; /* the ICP columns' frames per enum dao_motion_state */
	/* depth+ICP's accepted motion against the true one (poses.txt): frames, sums, maxima */
	long pose_n;
	double rot_sum, rot_max, tr_sum, tr_max;
	double px_sum, px_max; /* ... and the image displacement the difference makes */
	long pic_k;      /* the picture's frame, or -1 */
	float *pic;      /* its planes: input depth, truth, then the columns of pic_col */
};

/* Frame k: the input (as DEPTH16 in run->depth16 and metres), the truth where there is some. */
static int load_frame(struct seq_run *run, long k, struct dao_frame *frame, struct dao_error *err)
{
	struct seq_input *in = &run->in;
	const uint32_t w = in->cam.width, h = in->cam.height;
	*frame = (struct dao_frame){ .format = DAO_PIXFMT_DEPTH16, .width = w, .height = h,
				     .stride = (int32_t)(2 * w), .data = run->depth16,
				     .depth_unit = run->o->depth_unit };
	int r;
	if (in->oni) {
		r = dao_oni_reader_read_depth(in->oni, in->stream, (uint32_t)k, frame, err);
	} else {
		r = read_png_float(in->depth_dir, in->depth.names[k], &in->cam, 1.0, run->depth, err);
		for (size_t i = 0; !r && i < (size_t)w * h; i++)
			run->depth16[i] = (uint16_t)run->depth[i];
	}
	for (size_t i = 0; !r && i < (size_t)w * h; i++)
		run->depth[i] = run->depth16[i] * frame->depth_unit;
	if (!r && in->have_gt)
		r = read_png_float(in->gt_dir, in->gt.names[k], &in->cam, 1.0 / 65535.0, run->gt, err);
	if (!r && in->have_truth)
		r = read_png_float(in->truth_dir, in->truth.names[k], &in->cam, 0.001, run->truth, err);
	return r;
}

/* The mean distance (px) between where the estimate and the truth move this frame's
 * surface points (depth_gt/) in the last view: what the difference of the two motions
 * does to the reprojected histories (rotation and translation errors can cancel). */
static double pixel_error(const struct seq_run *run, const double *er, const double *et,
			  const double (*mr)[3], const double *mt)
{
	const struct dao_camera *cam = &run->in.cam;
	double sum = 0.0;
	long n = 0;
	for (uint32_t y = 0; y < cam->height; y += 4)
		for (uint32_t x = 0; x < cam->width; x += 4) {
			const double z = run->truth[(size_t)y * cam->width + x];
			if (!(z > 0.0))
				continue;
			const double p[3] = { (x - cam->cx) / cam->fx * z, (y - cam->cy) / cam->fy * z, z };
			double a[3], b[3];
			for (int i = 0; i < 3; i++) {
				a[i] = er[i * 3] * p[0] + er[i * 3 + 1] * p[1] + er[i * 3 + 2] * p[2] + et[i];
				b[i] = mr[i][0] * p[0] + mr[i][1] * p[1] + mr[i][2] * p[2] + mt[i];
			}
			if (!(a[2] > 0.0) || !(b[2] > 0.0))
				continue;
			sum += hypot(cam->fx * (a[0] / a[2] - b[0] / b[2]),
				     cam->fy * (a[1] / a[2] - b[1] / b[2]));
			n++;
		}
	return n ? sum / n : 0.0;
}

/* The motion column c's context accepted for frame k against poses.txt's, and its state. */
static void check_motion(struct seq_run *run, int c, long k)
{
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(run->ctx[c], &mi);
	run->motion[c][mi.state >= 0 && mi.state < 4 ? mi.state : 0]++;
	if (c != 3 || !run->in.have_poses || k < 1 || (long)run->in.poses.count <= k ||
	    (mi.state != DAO_MOTION_APPLIED && mi.state != DAO_MOTION_STILL))
		return;
	/* the truth from this camera to the last: M = P^T C (camera-to-world poses) */
	const struct synth_pose *P = &run->in.poses.pose[k - 1], *C = &run->in.poses.pose[k];
	double tr = 0.0, d2 = 0.0, mr[3][3], mt[3];
	for (int i = 0; i < 3; i++) {
		mt[i] = 0.0;
		for (int j = 0; j < 3; j++) {
			mr[i][j] = 0.0;
			for (int l = 0; l < 3; l++)
				mr[i][j] += P->R[l][i] * C->R[l][j];
			tr += mr[i][j] * mi.rotation[i * 3 + j]; /* trace(M^T E) */
			mt[i] += P->R[j][i] * (C->t[j] - P->t[j]);
		}
		d2 += (mi.translation[i] - mt[i]) * (mi.translation[i] - mt[i]);
	}
	if (run->in.have_truth) {
		const double px = pixel_error(run, mi.rotation, mi.translation, mr, mt);
		run->px_sum += px, run->px_max = fmax(run->px_max, px);
	}
	const double deg = acos(fmin(1.0, fmax(-1.0, 0.5 * (tr - 1.0)))) * 180.0 / M_PI;
	const double mm = sqrt(d2) * 1e3;
	run->pose_n++;
	run->rot_sum += deg, run->rot_max = fmax(run->rot_max, deg);
	run->tr_sum += mm, run->tr_max = fmax(run->tr_max, mm);
}

static int run_frames(struct seq_run *run)
{
	struct dao_error err;
	const uint32_t w = run->in.cam.width, h = run->in.cam.height;
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY_F32, .width = w, .height = h,
				.stride = (int32_t)(w * sizeof(float)), .data = run->ao };
	for (long k = 0; k < run->in.frames; k++) {
		struct dao_frame depth;
		if (load_frame(run, k, &depth, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		synth_seq_masks_add(&run->masks, run->depth, run->in.have_truth ? run->truth : NULL);
		const struct synth_pose *pose = run->tracking ? &run->in.poses.pose[k] : NULL;
		if (pose)
			synth_seq_track_frame(&run->track, run->truth, pose);
		for (int c = 0; c < NCOLS; c++) {
			if (dao_context_process(run->ctx[c], &depth, NULL, (uint64_t)k, &ao, &err)) {
				fprintf(stderr, "depthao: frame %ld: %s\n", k, err.message);
				return 1;
			}
			if (col_icp[c])
				check_motion(run, c, k);
			synth_seq_column_add(&run->cols[c], &run->masks, run->ao,
					     run->in.have_gt ? run->gt : NULL, run->depth, &run->res[k][c]);
			if (pose)
				synth_seq_column_track(&run->cols[c], &run->track, run->ao, run->depth,
						       run->truth, pose);
			if (run->o->settle) {
				synth_seq_column_add(&run->settled[c], &run->masks, run->ao, NULL,
						     run->depth, NULL);
				if (pose)
					synth_seq_column_track(&run->settled[c], &run->track, run->ao,
							       run->depth, run->truth, pose);
			}
			for (int j = 0; j < PIC_COLS && k == run->pic_k; j++)
				if (pic_col[j] == c)
					memcpy(run->pic + (size_t)(2 + j) * w * h, run->ao,
					       (size_t)w * h * sizeof(float));
		}
		if (k == run->pic_k) {
			memcpy(run->pic, run->depth, (size_t)w * h * sizeof(float));
			memcpy(run->pic + (size_t)w * h, run->gt, (size_t)w * h * sizeof(float));
		}
	}
	return 0;
}

/*
 * The picture (--picture): half-size panels, the truth and the columns of
 * pic_col side by side; above the AO (black 0, white 1), below the input
 * depth under the truth (near bright) and each column's |error| (white 0,
 * black >= 0.25).  Pixels without input depth are dark blue.
 */
static void picture_pixel(uint8_t *rgb, const float *pic, size_t np, int row, int k, size_t i,
			  float zmin, float zmax)
{
	static const uint8_t none[3] = { 20, 30, 90 };
	const float z = pic[i], gt = pic[np + i];
	const float v = pic[(size_t)(k == 0 ? 1 : 1 + k) * np + i];
	float g;
	if (!(z > 0.0f)) {
		memcpy(rgb, none, 3);
		return;
	}
	if (row == 0)
		g = v;
	else if (k == 0)
		g = 1.0f - 0.85f * (z - zmin) / (zmax - zmin);
	else
		g = 1.0f - fabsf(v - gt) / 0.25f;
	g = fminf(fmaxf(g, 0.0f), 1.0f);
	rgb[0] = rgb[1] = rgb[2] = (uint8_t)lrintf(255.0f * g);
}

static int write_picture(const struct seq_run *run)
{
	const int w = (int)run->in.cam.width, h = (int)run->in.cam.height;
	const int pw = w / 2, ph = h / 2, panels = 1 + PIC_COLS;
	const size_t np = (size_t)w * h;
	struct dao_frame pic = { 0 };
	struct dao_error err;
	float zmin = INFINITY, zmax = 0.0f;
	for (size_t i = 0; i < np; i++)
		if (run->pic[i] > 0.0f) {
			zmin = fminf(zmin, run->pic[i]);
			zmax = fmaxf(zmax, run->pic[i]);
		}
	if (!(zmax > zmin))
		zmax = zmin + 1.0f;
	if (dao_frame_alloc(&pic, DAO_PIXFMT_RGB24, (uint32_t)(panels * pw), (uint32_t)(2 * ph),
			    &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	for (int y = 0; y < 2 * ph; y++)
		for (int k = 0; k < panels; k++)
			for (int x = 0; x < pw; x++)
				picture_pixel((uint8_t *)pic.data + (size_t)y * pic.stride +
						      3 * (size_t)(k * pw + x),
					      run->pic, np, y >= ph, k,
					      (size_t)(2 * (y % ph)) * w + 2 * x, zmin, zmax);
	int r = dao_png_write_compressed(run->o->picture, &pic, 9, &err);
	if (r)
		fprintf(stderr, "depthao: %s\n", err.message);
	else
		printf("picture: %s (frame %ld: truth, %s, %s, %s; below: input depth, errors)\n",
		       run->o->picture, run->pic_k, col_names[pic_col[0]], col_names[pic_col[1]],
		       col_names[pic_col[2]]);
	dao_frame_free(&pic);
	return r ? 1 : 0;
}

static void print_frames(const struct seq_run *run)
{
	printf("| frame |");
	for (int c = 0; c < NCOLS; c++)
		printf(" MAE %s |", col_names[c]);
	for (int c = 0; c < NCOLS; c++)
		printf(" trail %s |", col_names[c]);
	printf(" trail px |\n|---:|");
	for (int c = 0; c < 2 * NCOLS + 1; c++)
		printf("---:|");
	printf("\n");
	for (long k = 0; k < run->in.frames; k++) {
		const struct synth_seq_frame *r = run->res[k];
		printf("| %ld |", k);
		for (int c = 0; c < NCOLS; c++)
			printf(" %.4f |", r[c].mae);
		for (int c = 0; c < NCOLS; c++)
			if (r[0].trail_count)
				printf(" %.4f |", r[c].trail_mae);
			else
				printf(" - |");
		printf(" %ld |\n", r[0].trail_count);
	}
}

/* The means (over frames; trails weighted by their pixels) and the frames worse than off. */
static void print_truth_summary(const struct seq_run *run)
{
	double mae[NCOLS] = { 0 }, trail[NCOLS] = { 0 };
	long tn = 0, worse[NCOLS] = { 0 };
	for (long k = 0; k < run->in.frames; k++) {
		const struct synth_seq_frame *r = run->res[k];
		for (int c = 0; c < NCOLS; c++) {
			mae[c] += r[c].mae / run->in.frames;
			trail[c] += r[c].trail_mae * r[c].trail_count;
			worse[c] += r[c].mae > r[0].mae + WORSE_EPS;
		}
		tn += r[0].trail_count;
	}
	printf("mean MAE:");
	for (int c = 0; c < NCOLS; c++)
		printf(" %s %.6f%s", col_names[c], mae[c], c + 1 < NCOLS ? "," : "\n");
	printf("gain over off:");
	for (int c = 1; c < NCOLS; c++)
		printf(" %s %.1f %%%s", col_names[c],
		       mae[0] > 0 ? 100.0 * (mae[0] - mae[c]) / mae[0] : 0.0, c + 1 < NCOLS ? "," : "\n");
	printf("frames worse than off (by > %g):", WORSE_EPS);
	for (int c = 1; c < NCOLS; c++)
		printf(" %s %ld%s", col_names[c], worse[c], c + 1 < NCOLS ? "," : "");
	printf(" (of %ld)\n", run->in.frames);
	if (tn) {
		printf("trail MAE (%ld px):", tn);
		for (int c = 0; c < NCOLS; c++)
			printf(" %s %.6f%s", col_names[c], trail[c] / tn, c + 1 < NCOLS ? "," : "\n");
	} else if (run->in.have_truth) {
		printf("trail MAE: no discontinuity moved\n");
	}
}

/* "off A, depth B, ... (off/depth Nx, ...)" of one figure per column */
static void print_columns(const double *v, int ratios)
{
	for (int c = 0; c < NCOLS; c++)
		printf("%s %s %.6f", c ? "," : "", col_names[c], v[c]);
	if (ratios)
		for (int c = 1; c < NCOLS; c++)
			printf("%soff/%s %.2fx", c == 1 ? " (" : ", ", col_names[c],
			       v[c] > 1e-6 ? v[0] / v[c] : 1.0);
	printf("%s\n", ratios ? ")" : "");
}

/* The flicker line of one set of columns; `from`: the first frame they
 * measured (0: all) */
static void print_flicker(const struct seq_run *run, const struct synth_seq_column *cols,
			  long from)
{
	const struct seq_input *in = &run->in;
	long n;
	double fl[NCOLS];
	for (int c = 0; c < NCOLS; c++)
		fl[c] = run->tracking ? synth_seq_flicker_tracked(&cols[c], &run->track, &n)
				      : synth_seq_flicker(&cols[c], &run->masks, &n);
	char what[64] = "";
	if (from)
		snprintf(what, sizeof what, " from frame %ld (%ld frames)", from, in->frames - from);
	if (run->tracking && n && in->frames - from > 1) {
		printf("flicker%s (tracked over the true poses, %ld surface points seen in every "
		       "frame):", what, n);
		print_columns(fl, 1);
	} else if (in->camera_moves) {
		printf("flicker%s: - (the camera moves: without depth_gt/ the surface points cannot "
		       "be followed)\n", what);
	} else if (n == 0 || in->frames - from < 2) {
		printf("flicker%s: - (no pixel is static with depth in every frame)\n", what);
	} else {
		printf("flicker%s (%ld static px):", what, n);
		print_columns(fl, 1);
	}
}

static void print_summary(const struct seq_run *run)
{
	const struct seq_input *in = &run->in;
	if (in->have_gt) {
		print_frames(run);
		print_truth_summary(run);
	}
	double ch[NCOLS];
	for (int c = 0; c < NCOLS; c++)
		ch[c] = synth_seq_change(&run->cols[c]);
	print_flicker(run, run->cols, 0);
	printf("change (mean |AO_k - AO_k-1|):");
	print_columns(ch, 0);
	if (run->o->settle) {
		print_flicker(run, run->settled, run->o->settle);
		for (int c = 0; c < NCOLS; c++)
			ch[c] = synth_seq_change(&run->settled[c]);
		printf("change from frame %ld:", run->o->settle);
		print_columns(ch, 0);
	}
	for (int c = 0; c < NCOLS; c++)
		if (col_icp[c])
			printf("motion %s: applied %ld, still %ld, refused %ld, none %ld (frames)\n",
			       col_names[c], run->motion[c][DAO_MOTION_APPLIED],
			       run->motion[c][DAO_MOTION_STILL], run->motion[c][DAO_MOTION_REFUSED],
			       run->motion[c][DAO_MOTION_NONE]);
	if (run->pose_n)
		printf("motion error of depth+ICP against poses.txt (%ld accepted frames): rotation "
		       "mean %.4f, max %.4f deg; translation mean %.3f, max %.3f mm\n", run->pose_n,
		       run->rot_sum / run->pose_n, run->rot_max, run->tr_sum / run->pose_n,
		       run->tr_max);
	if (run->pose_n && run->in.have_truth)
		printf("image displacement of that error (mean over the true surface points): mean "
		       "%.3f, max %.3f px\n", run->px_sum / run->pose_n, run->px_max);
}

static int setup_run(struct seq_run *run)
{
	const struct seq_options *o = run->o;
	struct seq_input *in = &run->in;
	if (o->max_frames && in->frames > o->max_frames)
		in->frames = o->max_frames;
	if (in->frames < 1) {
		fprintf(stderr, "depthao: %s: no depth frames\n", o->path);
		return 1;
	}
	const size_t np = (size_t)in->cam.width * in->cam.height;
	run->depth16 = malloc(np * sizeof *run->depth16);
	run->depth = malloc(np * sizeof(float));
	run->gt = malloc(np * sizeof(float));
	run->truth = malloc(np * sizeof(float));
	run->ao = malloc(np * sizeof(float));
	run->res = calloc((size_t)in->frames, sizeof *run->res);
	run->pic_k = !o->picture ? -1 : o->picture_frame < 0 ? in->frames - 1 : o->picture_frame;
	if (run->pic_k >= in->frames) {
		fprintf(stderr, "depthao: --picture-frame %ld: the sequence has %ld frames\n",
			run->pic_k, in->frames);
		return 2;
	}
	if (o->settle && o->settle > in->frames - 2) {
		fprintf(stderr, "depthao: --settle %ld: the sequence has %ld frames; the flicker "
			"from frame K needs K + 2 frames at least (%ld here)\n",
			o->settle, in->frames, o->settle + 2);
		return 2;
	}
	if (o->picture && !in->have_gt) {
		fprintf(stderr, "depthao: --picture needs the truth (ao_gt/ beside depth/)\n");
		return 2;
	}
	if (run->pic_k >= 0)
		run->pic = malloc((2 + PIC_COLS) * np * sizeof(float));
	int bad = !run->depth16 || !run->depth || !run->gt || !run->truth || !run->ao || !run->res ||
		  (run->pic_k >= 0 && !run->pic) ||
		  synth_seq_masks_init(&run->masks, (int)in->cam.width, (int)in->cam.height,
				       in->have_truth);
	for (int c = 0; c < NCOLS && !bad; c++)
		bad = synth_seq_column_init(&run->cols[c], (int)in->cam.width, (int)in->cam.height);
	for (int c = 0; c < NCOLS && !bad && o->settle; c++) {
		bad = synth_seq_column_init(&run->settled[c], (int)in->cam.width,
					    (int)in->cam.height);
		run->settled[c].skip = o->settle;
	}
	run->tracking = in->have_truth && in->have_poses && (long)in->poses.count >= in->frames;
	if (in->have_poses && (long)in->poses.count < in->frames)
		fprintf(stderr, "depthao: warning: %s has %zu poses for %ld frames: not used\n",
			in->pose_path, in->poses.count, in->frames);
	if (!bad && run->tracking)
		bad = synth_seq_track_init(&run->track, (int)in->cam.width, (int)in->cam.height,
					   in->cam.fx, in->cam.fy, in->cam.cx, in->cam.cy);
	if (bad) {
		fprintf(stderr, "depthao: out of memory\n");
		return 1;
	}
	for (int c = 0; c < NCOLS; c++) {
		struct dao_params p;
		struct dao_error err;
		if (column_params(o, c, &p))
			return 2;
		if (dao_context_create(&run->ctx[c], &in->cam, &p, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
	}
	return 0;
}

static void free_run(struct seq_run *run)
{
	for (int c = 0; c < NCOLS; c++) {
		dao_context_destroy(run->ctx[c]);
		synth_seq_column_free(&run->cols[c]);
		synth_seq_column_free(&run->settled[c]);
	}
	synth_seq_masks_free(&run->masks);
	synth_seq_track_free(&run->track);
	free(run->depth16);
	free(run->depth);
	free(run->gt);
	free(run->truth);
	free(run->ao);
	free(run->res);
	free(run->pic);
	close_input(&run->in);
}

int cmd_eval_sequence(int argc, char **argv)
{
	struct seq_options o;
	int status = parse_args(argc, argv, &o);
	if (status)
		return status;
	struct seq_run run = { .o = &o };
	if (ends_with(o.path, ".oni"))
		status = open_oni(&o, &run.in);
	else
		status = open_png_dirs(&o, &run.in);
	if (!status)
		status = setup_run(&run);
	if (!status) {
		printf("sequence %s: %ld frames, %ux%u, truth: %s, trail band: %s, camera: %s\n", o.path,
		       run.in.frames, run.in.cam.width, run.in.cam.height, run.in.have_gt ? "yes" : "no",
		       run.in.have_truth ? "yes" : "no (no depth_gt/)",
		       !run.in.have_poses ? "no poses" : run.in.camera_moves ? "moves" : "still");
		status = run_frames(&run);
	}
	if (!status)
		print_summary(&run);
	if (!status && run.pic)
		status = write_picture(&run);
	free_run(&run);
	return status;
}
