/* SPDX-License-Identifier: MIT */
/*
 * depthao process: a 16-bit depth PNG, or a directory of them, to AO
 * (16-bit PNG, round(visibility x 65535)) and occlusion-shaded RGB PNGs.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "common/tool_clock.h"
#include "common/camera_file.h"
#include "cli_params.h"
#include "commands.h"
#include "file_list.h"
#include "common/pixel_limit.h"
#include "process.h"
#include "poses_file.h"
#include "progress.h"
#include <json-c/json.h>



static void usage(FILE *out)
{
	struct dao_params def, stream;
	dao_params_init(&def, DAO_QUALITY_DEFAULT);
	stream = def;
	dao_params_stream_defaults(&stream);
	fprintf(out,
		"usage: depthao process --input PATH|URI [--ao-out PATH] [--shaded-out PATH]\n"
		"                       [--overlay-out DIR] [--cloud-out DIR|FILE.ply]\n"
		"                       [--mcap-out FILE.mcap] [--depth-out PATH] [options]\n"
		"\n"
		"Computes ambient occlusion for a 16-bit depth PNG, for every *.png of a\n"
		"directory (sorted by name; then the outputs are directories with the same file\n"
		"names, created if missing), or for every frame of a recording or device (the\n"
		"outputs are directories of 000000.png, 000001.png, ... numbered by frame).\n"
		"At least one output is required.\n"
		"\n"
		"Recordings and devices are streams of consecutive frames: they also run the\n"
		"temporal depth filter (--depth-temporal %.1f; --depth-temporal 0 turns it off)\n"
		"and measure the noise fully every %d frames, and where the scene moved in\n"
		"between (--noise-interval 1: every frame).  PNG input does neither (its files\n"
		"need not follow each other: each file's result is its own; give the options to\n"
		"have them).\n"
		"\n"
		"  --input PATH|URI          depth PNG, directory of depth PNGs, .oni recording, or\n"
		"                            a source URI NAME:ARG (oni:FILE, openni2:any,\n"
		"                            openni2:FILE.oni; 'depthao devices' lists them)\n"
		"  --start N                 recordings: first frame, 0-based (default 0)\n"
		"  --frames N                at most N frames (required for live devices)\n"
		"  --realtime                recordings: pace frames by their timestamps\n"
		"  --poses FILE              PNG directory: the camera's pose per frame, TUM format\n"
		"                            ('timestamp tx ty tz qx qy qz qw'); a frame's time is\n"
		"                            its file name (1305031102.160407.png) or its index /\n"
		"                            camera.json's fps (default 30).  Sets\n"
		"                            --depth-temporal-motion source unless given\n"
		"  --pose-frame NAME         ROS and Foxglove recordings with --depth-temporal-motion\n"
		"                            source or source+icp: the fixed frame of the camera\n"
		"                            poses taken from the tf or foxglove.FrameTransform(s)\n"
		"                            (default: the root of the depth frame's tree, e.g. odom\n"
		"                            or map)\n"
		"  --pose-topic TOPIC        ... from this nav_msgs/Odometry topic (and the static\n"
		"                            tf to the camera) instead of the tf, this Foxglove\n"
		"                            PoseInFrame(s), sensor_msgs/Imu (a rotation alone: use\n"
		"                            source+icp) or one topic of transforms (+ the static)\n"
		"  --pose-gap S              ... the longest time between two transforms that a\n"
		"                            pose is interpolated over (default 0.5 s)\n"
		"  --ao-out PATH             AO as 16-bit PNG: round(visibility x 65535), 65535 = open\n"
		"  --shaded-out PATH         occlusion-shaded 8-bit RGB PNG\n"
		"  --overlay-out DIR         recordings and devices with colour: the colour image\n"
		"                            darkened by the AO (8-bit RGB PNG, the depth's size;\n"
		"                            colour of the depth's aspect ratio is scaled, others\n"
		"                            are refused); a depth-only input is an error\n"
		"  --cloud-out DIR|FILE.ply  point clouds: binary PLY of the pixels with depth, x y z\n"
		"                            in metres (optical frame: x right, y down, z forward),\n"
		"                            the AO as grey colour and as the property scalar_ao;\n"
		"                            a directory gets one file per frame (NAME.ply, or\n"
		"                            000000.ply ... for recordings), FILE.ply one frame only\n"
		"  --mcap-out FILE.mcap      the AO (Image mono16), shaded image (rgb8) and CameraInfo\n"
		"                            of every frame as ROS 2 messages in one MCAP file (zstd\n"
		"                            chunks); FILE.mcap?cloud=true adds the AO point cloud\n"
		"                            (PointCloud2 x y z ao); options: docs/sinks.md\n"
		"  --depth-out PATH          the filtered depth (the depth the AO was computed from,\n"
		"                            after depth-min/max, the temporal filter and the\n"
		"                            prefilter) as 16-bit PNG in the input's unit, 0 = no\n"
		"                            depth; with --algorithm none the only work done\n"
		"  --pose-out FILE           the camera pose of every frame as estimated from the\n"
		"                            depth (needs --depth-temporal-motion icp), TUM format:\n"
		"                            timestamp tx ty tz qx qy qz qw, camera to the first\n"
		"                            frame's optical frame (docs/motion.md)\n"
		"  --pose-fps N              --pose-out of PNG input: timestamps frame / N s\n"
		"                            (default 30)\n"
		"  --depth-out-unit M        --depth-out in counts of M metres (default: the\n"
		"                            input's unit; 0.001 = mm for float-metre input)\n"
		"  --cloud-depth raw|filtered  --cloud-out from the input depth (raw, the default:\n"
		"                            the sensor's measurement) or the filtered depth\n"
		"  --depth-unit M            PNG input and 16-bit bag topics: metres per count\n"
		"                            (default 0.001; TUM: 0.0002); .oni and RealSense\n"
		"                            recordings carry their own unit\n"
		"  --max-pixels N|WxH        largest depth image decoded from a file, in pixels\n"
		"                            (default 4096x4096); larger PNGs and recordings are\n"
		"                            refused before any memory is allocated for them\n"
		"  --intrinsics FX,FY,CX,CY  pinhole intrinsics in pixels\n"
		"  --fov H,V                 field of view in degrees (OpenNI style)\n"
		"  --intrinsics-file FILE    Open3D camera JSON (width, height, intrinsic_matrix)\n"
		"                            or ROS CameraInfo YAML (camera_info_manager's format;\n"
		"                            with distortion: a warning, the depth must be\n"
		"                            rectified, and the projection matrix is used)\n"
		"                            without any of these: the recording's intrinsics (a\n"
		"                            bag's CameraInfo) or field of view, or camera.json\n"
		"                            (else camera.yaml) beside PNG input, else a %.1f x %.1f\n"
		"                            degree field of view\n"
		"  --quality Q               preset: low, medium, high, ultra, default (= medium)\n"
		"  --frame-index N           noise pattern of the first frame (default 0)\n"
		"  --quiet                   no progress bar or summary\n"
		"  --help                    this text\n"
		"\n"
		"AO parameters (override the preset; defaults are the medium preset):\n",
		(double)stream.depth_temporal, stream.noise_interval, DEFAULT_HFOV_DEG,
		DEFAULT_VFOV_DEG);
	cli_print_param_help(out, &def);
}

void process_print_error(const struct dao_error *err)
{
	fprintf(stderr, "depthao: %s%s\n", err->message,
		err->code == -EFBIG ? " (--max-pixels raises the limit)" : "");
}

static int parse_double(const char *s, double *out)
{
	char *end;
	errno = 0;
	double v = strtod(s, &end);
	if (end == s || *end || errno || !isfinite(v))
		return -1;
	*out = v;
	return 0;
}

/* "a,b,c" into n doubles. */
static int parse_list(const char *s, double *v, int n)
{
	char buf[256];
	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	int k = 0;
	char *save = NULL;
	for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		if (k == n || parse_double(tok, &v[k]))
			return -1;
		k++;
	}
	return k == n ? 0 : -1;
}

static const char *option_value(int argc, char **argv, int *i, const char *name)
{
	const char *a = argv[*i];
	size_t n = strlen(name);
	if (strncmp(a, name, n) != 0)
		return NULL;
	if (a[n] == '=')
		return a + n + 1;
	if (a[n] != '\0')
		return NULL;
	if (*i + 1 >= argc)
		return "";
	return argv[++*i];
}

/* The preset, wherever --quality appears (parameter options override it): 0 or the exit status. */
static int preset_option(int argc, char **argv, enum dao_quality *q)
{
	for (int i = 1; i < argc; i++) {
		const char *v = option_value(argc, argv, &i, "--quality");
		if (!v)
			continue;
		struct dao_error err;
		if (!*v)
			return usage_error("process", "--quality needs a value");
		if (dao_quality_parse(v, q, &err))
			return usage_error("process", "%s", err.message);
	}
	return 0;
}

/*
 * A recording or device is a stream of consecutive frames: the temporal
 * depth filter too (a directory of images may be anything: not there);
 * before the parameter options, so that --depth-temporal 0 turns it off.
 */
static void stream_defaults_for_input(int argc, char **argv, struct dao_params *p)
{
	for (int i = 1; i < argc; i++) {
		const char *v = option_value(argc, argv, &i, "--input");
		if (v && *v && process_input_is_stream(v) && strncmp(v, "images:", 7) != 0)
			dao_params_stream_defaults(p);
	}
}

/*
 * The options below parse the option at argv[*i] if it is theirs (moving *i
 * past its value): -1 if it is not, 0 if parsed, else the exit status.
 */

/* --input, the outputs and the camera: kept as given. */
static int string_option(int argc, char **argv, int *i, struct process_options *o)
{
	const struct {
		const char *name;
		const char **dst;
	} strings[] = {
		{ "--input", &o->input }, { "--ao-out", &o->ao_out },
		{ "--shaded-out", &o->shaded_out }, { "--overlay-out", &o->overlay_out },
		{ "--cloud-out", &o->cloud_out }, { "--mcap-out", &o->mcap_out },
		{ "--depth-out", &o->depth_out }, { "--pose-out", &o->pose_out },
		{ "--poses", &o->poses }, { "--pose-frame", &o->pose_frame },
		{ "--pose-topic", &o->pose_topic }, { "--pose-gap", &o->pose_gap },
		{ "--intrinsics", &o->intrinsics },
		{ "--fov", &o->fov }, { "--intrinsics-file", &o->intrinsics_file },
	};
	for (size_t k = 0; k < sizeof strings / sizeof strings[0]; k++) {
		int j = *i;
		const char *v = option_value(argc, argv, &j, strings[k].name);
		if (v) {
			if (!*v)
				return usage_error("process", "%s needs a value", strings[k].name);
			*strings[k].dst = v;
			*i = j;
			return 0;
		}
	}
	return -1;
}

/* --quality (applied before), --depth-unit and --max-pixels. */
static int input_option(int argc, char **argv, int *i, struct process_options *o)
{
	int j = *i;
	const char *v;
	if ((v = option_value(argc, argv, &j, "--quality"))) {
		*i = j; /* applied before */
		return 0;
	}
	if ((v = option_value(argc, argv, &j, "--depth-unit"))) {
		if (!*v || parse_double(v, &o->depth_unit) || o->depth_unit <= 0 ||
		    o->depth_unit > 1)
			return usage_error("process",
					   "--depth-unit '%s' must be a number in (0, 1] metres per count",
					   v);
		*i = j;
		return 0;
	}
	if ((v = option_value(argc, argv, &j, "--pose-fps"))) {
		if (!*v || parse_double(v, &o->pose_fps) || !(o->pose_fps > 0) || o->pose_fps > 1e6)
			return usage_error("process", "--pose-fps '%s' must be a frame rate in (0, 1e6]",
					   v);
		*i = j;
		return 0;
	}
	if ((v = option_value(argc, argv, &j, "--depth-out-unit"))) {
		if (!*v || parse_double(v, &o->depth_out_unit) || !(o->depth_out_unit > 0) ||
		    o->depth_out_unit > 1)
			return usage_error("process", "--depth-out-unit '%s' must be a number in "
					   "(0, 1] metres per count (0.001 = mm)", v);
		*i = j;
		return 0;
	}
	if ((v = option_value(argc, argv, &j, "--cloud-depth"))) {
		if (strcmp(v, "raw") != 0 && strcmp(v, "filtered") != 0)
			return usage_error("process", "--cloud-depth '%s' must be raw or filtered", v);
		o->cloud_filtered = v[0] == 'f';
		*i = j;
		return 0;
	}
	if ((v = option_value(argc, argv, &j, "--max-pixels"))) {
		if (pixel_limit_parse(v, &o->max_pixels))
			return usage_error("process",
					   "--max-pixels '%s' must be a pixel count or WxH, "
					   "at most 16384x16384", v);
		*i = j;
		return 0;
	}
	return -1;
}

/* --start, --frames and --frame-index. */
static int frame_option(int argc, char **argv, int *i, struct process_options *o)
{
	int j = *i;
	const char *v;
	if ((v = option_value(argc, argv, &j, "--start")) ||
	    (v = option_value(argc, argv, &j, "--frames"))) {
		const char *name = strncmp(argv[*i], "--start", 7) == 0 ? "--start" : "--frames";
		char *end;
		errno = 0;
		unsigned long n = strtoul(v, &end, 10);
		if (!*v || *end || errno || v[0] == '-' || n > UINT32_MAX ||
		    (n == 0 && name[2] == 'f'))
			return usage_error("process", "%s '%s' must be a %s integer", name, v,
					   name[2] == 'f' ? "positive" : "non-negative");
		*(name[2] == 's' ? &o->start : &o->max_frames) = (uint32_t)n;
		*i = j;
		return 0;
	}
	if ((v = option_value(argc, argv, &j, "--frame-index"))) {
		char *end;
		errno = 0;
		unsigned long long n = strtoull(v, &end, 10);
		if (!*v || *end || errno || v[0] == '-')
			return usage_error("process", "--frame-index '%s' is not a non-negative integer", v);
		o->frame_index = n;
		*i = j;
		return 0;
	}
	return -1;
}

int process_camera_options(struct process_options *o)
{
	const char *cmd = o->cmd ? o->cmd : "process";
	if (!!o->intrinsics + !!o->fov + !!o->intrinsics_file > 1)
		return usage_error(cmd, "give only one of --intrinsics, --fov and --intrinsics-file");
	if (o->intrinsics && parse_list(o->intrinsics, o->k, 4))
		return usage_error(cmd, "--intrinsics '%s' must be four numbers FX,FY,CX,CY",
				   o->intrinsics);
	if (o->fov && (parse_list(o->fov, o->f, 2) || !(o->f[0] > 0 && o->f[0] < 180) ||
		       !(o->f[1] > 0 && o->f[1] < 180)))
		return usage_error(cmd, "--fov '%s' must be two angles H,V in (0, 180) degrees",
				   o->fov);
	return 0;
}

/* What the options say together: an input, an output, one camera: 0 or the exit status. */
static int check_options(struct process_options *o)
{
	if (!o->input)
		return usage_error("process", "--input is required");
	if (!o->ao_out && !o->shaded_out && !o->overlay_out && !o->cloud_out && !o->mcap_out &&
	    !o->depth_out && !o->pose_out)
		return usage_error("process", "nothing to write: give --ao-out, --shaded-out, "
				   "--overlay-out, --cloud-out, --mcap-out, --depth-out and/or "
				   "--pose-out");
	if (o->pose_out && ((o->params.depth_temporal_motion == DAO_DEPTH_MOTION_OFF && !o->poses) ||
			    !(o->params.depth_temporal > 0.0f)))
		return usage_error("process", "--pose-out writes the camera motion that "
				   "depth-temporal-motion follows: give --depth-temporal-motion icp "
				   "(or --poses FILE)%s",
				   o->params.depth_temporal > 0.0f ? ""
				   : " and the temporal depth filter (--depth-temporal 0.8)");
	if (o->params.algorithm == DAO_ALGORITHM_NONE &&
	    (o->shaded_out || o->overlay_out || o->mcap_out))
		return usage_error("process", "--algorithm none computes the filtered depth only (no "
				   "AO to shade or record): give --depth-out, or an AO algorithm "
				   "for %s", o->shaded_out ? "--shaded-out" : o->overlay_out
				   ? "--overlay-out" : "--mcap-out");
	if (o->overlay_out && !process_input_is_stream(o->input))
		return usage_error("process", "--overlay-out needs colour, and '%s' is depth-only PNG "
				   "input: give a recording or device with colour (.oni, .bag, "
				   "openni2:...)", o->input);
	int status = process_camera_options(o);
	if (status)
		return status;
	if (o->poses && process_input_is_stream(o->input))
		return usage_error("process", "--poses applies to PNG directories; a ROS "
				   "recording's own tf or odometry is used with "
				   "--depth-temporal-motion source (docs/motion.md)");
	if ((o->pose_frame || o->pose_topic || o->pose_gap) &&
	    (!process_input_is_stream(o->input) || !process_wants_source_poses(o)))
		return usage_error("process", "--pose-frame, --pose-topic and --pose-gap say how a "
				   "ROS or Foxglove recording's (.bag, .mcap, .db3) poses are read: "
				   "give such a recording and --depth-temporal-motion source or "
				   "source+icp");
	if (o->poses && !(o->params.depth_temporal > 0.0f))
		return usage_error("process", "--poses moves the temporal depth filter's history "
				   "with the camera: give --depth-temporal X (e.g. 0.8) too");
	if (o->poses && o->params.depth_temporal_motion == DAO_DEPTH_MOTION_OFF)
		o->params.depth_temporal_motion = DAO_DEPTH_MOTION_SOURCE;
	struct dao_error err;
	if (dao_params_validate(&o->params, &err))
		return usage_error("process", "%s", err.message);
	return 0;
}

static int parse_args(int argc, char **argv, struct process_options *o)
{
	memset(o, 0, sizeof *o);
	o->depth_unit = 0.001;
	o->pose_fps = 30.0;
	enum dao_quality q = DAO_QUALITY_DEFAULT;
	int status = preset_option(argc, argv, &q);
	if (status)
		return status;
	dao_params_init(&o->params, q);
	stream_defaults_for_input(argc, argv, &o->params);
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			usage(stdout);
			exit(0);
		}
		if (strcmp(a, "--quiet") == 0) {
			o->quiet = 1;
			continue;
		}
		if (strcmp(a, "--realtime") == 0) {
			o->realtime = 1;
			continue;
		}
		if ((status = string_option(argc, argv, &i, o)) >= 0 ||
		    (status = input_option(argc, argv, &i, o)) >= 0 ||
		    (status = frame_option(argc, argv, &i, o)) >= 0) {
			if (status)
				return status;
			continue;
		}
		/* the AO parameters, over the preset */
		char msg[DAO_ERROR_MESSAGE_MAX];
		int r = cli_apply_param_option(&o->params, argc, argv, &i, msg, sizeof msg);
		if (r < 0)
			return usage_error("process", "%s", msg);
		if (r == 0)
			return usage_error("process", "unknown option '%s'", a);
	}
	return check_options(o);
}

/* The camera for images of w x h, from the options, a camera.json beside the input, or a default. */
int process_resolve_camera(const struct process_options *o, uint32_t w, uint32_t h,
			   const struct dao_source_info *src, struct dao_camera *cam)
{
	struct dao_error err;
	char msg[512];
	const char *cmd = o->cmd ? o->cmd : "process";
	if (o->intrinsics) {
		if (dao_camera_from_intrinsics(cam, w, h, o->k[0], o->k[1], o->k[2], o->k[3], &err))
			return usage_error(cmd, "--intrinsics: %s", err.message);
		return 0;
	}
	if (o->fov) {
		if (dao_camera_from_fov(cam, w, h, o->f[0] * DEG2RAD, o->f[1] * DEG2RAD, &err))
			return usage_error(cmd, "--fov: %s", err.message);
		return 0;
	}
	if (src && src->has_intrinsics && !o->intrinsics_file) {
		if (dao_camera_from_intrinsics(cam, w, h, src->fx, src->fy, src->cx, src->cy, &err))
			return usage_error(cmd, "the source's intrinsics: %s", err.message);
		if (!o->quiet)
			fprintf(stderr, "depthao: intrinsics from the source: fx %.2f fy %.2f cx %.2f "
				"cy %.2f\n", src->fx, src->fy, src->cx, src->cy);
		return 0;
	}
	if (src && src->has_fov && !o->intrinsics_file) {
		if (dao_camera_from_fov(cam, w, h, src->hfov, src->vfov, &err))
			return usage_error(cmd, "the source's field of view: %s", err.message);
		if (!o->quiet)
			fprintf(stderr, "depthao: field of view from the source: %.2f x %.2f degrees\n",
				src->hfov / DEG2RAD, src->vfov / DEG2RAD);
		return 0;
	}
	const char *file = o->intrinsics_file;
	char beside[4096 + 16];
	/* PNG input (also as the images source): camera.json beside it */
	int found = file ? 0 : camera_file_beside(src ? process_input_path(o->input) : o->input,
						   beside, sizeof beside);
	if (found < 0) {
		fprintf(stderr, "depthao: the camera file beside the input, %s, cannot be read: %s "
			"(make it readable, or give --intrinsics-file, --intrinsics or --fov)\n",
			beside, strerror(errno));
		return 1;
	}
	if (found) {
		file = beside;
		if (!o->quiet)
			fprintf(stderr, "depthao: using intrinsics from %s\n", file);
	}
	if (file) {
		if (camera_file_read(file, cam, msg, sizeof msg)) {
			fprintf(stderr, "depthao: %s\n", msg);
			return 1;
		}
		if (cam->width != w || cam->height != h) {
			fprintf(stderr, "depthao: camera file '%s' is for %ux%u images, the input is "
				"%ux%u\n", file, cam->width, cam->height, w, h);
			return 1;
		}
		return 0;
	}
	fprintf(stderr,
		"depthao: warning: no intrinsics given; assuming a %.1f x %.1f degree field of view "
		"(use --intrinsics, --fov or --intrinsics-file)\n", DEFAULT_HFOV_DEG, DEFAULT_VFOV_DEG);
	dao_camera_from_fov(cam, w, h, DEFAULT_HFOV_DEG * DEG2RAD,
			    DEFAULT_VFOV_DEG * DEG2RAD, NULL);
	return 0;
}

/* Creates an output directory and its missing parents (mkdir -p). */
int process_ensure_dir(const char *path)
{
	if (!strcmp(path, "-")) {
		fprintf(stderr, "depthao: '-' (standard output) takes one file, and this input "
			"writes one file per frame or image: give a directory (./- for one named "
			"'-')\n");
		return 1;
	}
	int d = path_is_dir(path);
	if (d == 1)
		return 0;
	if (d == 0) {
		fprintf(stderr, "depthao: output '%s' exists and is not a directory\n", path);
		return 1;
	}
	char *parent = path_dirname(path);
	int r = parent && strcmp(parent, path) != 0 && path_is_dir(parent) < 0 ? process_ensure_dir(parent) : 0;
	free(parent);
	if (r)
		return r;
	if (mkdir(path, 0777) != 0 && errno != EEXIST) {
		fprintf(stderr, "depthao: cannot create output directory '%s': %s\n", path,
			strerror(errno));
		return 1;
	}
	return 0;
}

double process_now_ms(void)
{
	return (double)tool_mono_ns() * 1e-6;
}


int process_cloud_is_file(const struct process_options *o)
{
	size_t n = o->cloud_out ? strlen(o->cloud_out) : 0;
	struct stat st;
	if ((n > 4 && !strcasecmp(o->cloud_out + n - 4, ".ply")) || (n == 1 && *o->cloud_out == '-'))
		return 1; /* "-": one cloud to standard output */
	/* a FIFO or character device (/dev/stdout on a pipe, /dev/null), an existing file */
	return n && stat(o->cloud_out, &st) == 0 && !S_ISDIR(st.st_mode);
}

int process_check_cloud_frames(const struct process_options *o, uint64_t frames, int stream)
{
	if (frames <= 1 || !process_cloud_is_file(o))
		return 0;
	return usage_error("process",
			   "--cloud-out '%s' is one file, but the input has %llu frames: give a "
			   "directory (one .ply per frame)%s", o->cloud_out,
			   (unsigned long long)frames, stream ? " or --frames 1" : "");
}

char *process_cloud_name(const char *dir, const char *input_name)
{
	const char *base = path_basename(input_name);
	const char *dot = strrchr(base, '.');
	size_t n = dot && dot != base ? (size_t)(dot - base) : strlen(base);
	char name[512];
	if (n > sizeof name - 5)
		n = sizeof name - 5;
	memcpy(name, base, n);
	memcpy(name + n, ".ply", 5);
	return path_join(dir, name);
}

/*
 * The filtered depth of the frame just processed, to `path` as a 16-bit PNG: counts of
 * --depth-out-unit, else of the input's unit, else (float-metre input) millimetres.
 */
static int write_filtered_depth(const struct process_options *o, struct run_state *st,
				const struct dao_frame *depth, const char *path,
				struct dao_error *err)
{
	double unit = o->depth_out_unit > 0 ? o->depth_out_unit
		      : depth->format == DAO_PIXFMT_DEPTH16 ? (double)depth->depth_unit
		      : PROCESS_FLOAT_DEPTH_OUT_UNIT;
	st->depth16.depth_unit = (float)unit;
	int r = dao_context_get_depth(st->ctx, &st->depth16, err);
	return r ? r : dao_png_write(path, &st->depth16, err);
}

int process_alloc_depth_outputs(const struct process_options *o, struct run_state *st,
				uint32_t w, uint32_t h, struct dao_error *err)
{
	int r = 0;
	if (o->depth_out)
		r = dao_frame_alloc(&st->depth16, DAO_PIXFMT_DEPTH16, w, h, err);
	if (!r && o->cloud_out && o->cloud_filtered)
		r = dao_frame_alloc(&st->depth_m, DAO_PIXFMT_DEPTH_F32, w, h, err);
	return r;
}

void process_free_outputs(struct run_state *st)
{
	dao_frame_free(&st->ao);
	dao_frame_free(&st->rgb);
	dao_frame_free(&st->overlay);
	dao_frame_free(&st->depth16);
	dao_frame_free(&st->depth_m);
}

int process_depth(const struct process_options *o, struct run_state *st,
		  const struct dao_frame *depth, const struct dao_frame *color,
		  const struct process_paths *paths, uint64_t index)
{
	const char *ao_path = paths->ao, *shaded_path = paths->shaded;
	struct dao_error err;
	const struct dao_camera *cam = dao_context_camera(st->ctx);
	if (depth->width != cam->width || depth->height != cam->height) {
		fprintf(stderr, "depthao: frame %llu is %ux%u, but the sequence is %ux%u\n",
			(unsigned long long)index, depth->width, depth->height, cam->width,
			cam->height);
		return 1;
	}
	double t0 = process_now_ms();
	int r = dao_context_process(st->ctx, depth, NULL, index, &st->ao, &err);
	st->ms_total += process_now_ms() - t0;
	st->frames++;
	if (!r && process_pose_write(o, st, depth, st->frames - 1))
		return 1;
	if (!r && ao_path)
		r = dao_png_write(ao_path, &st->ao, &err);
	if (!r && shaded_path) {
		r = dao_context_shade(st->ctx, &st->rgb, &err);
		if (!r)
			r = dao_png_write(shaded_path, &st->rgb, &err);
	}
	if (!r && paths->overlay) {
		if (!color || color->format != DAO_PIXFMT_RGB24) {
			fprintf(stderr, "depthao: frame %llu came without its colour image\n",
				(unsigned long long)index);
			return 1;
		}
		r = dao_overlay(color, &st->ao, &st->overlay, &err);
		if (!r)
			r = dao_png_write(paths->overlay, &st->overlay, &err);
	}
	if (!r && paths->depth)
		r = write_filtered_depth(o, st, depth, paths->depth, &err);
	if (!r && paths->cloud && o->cloud_filtered)
		r = dao_context_get_depth(st->ctx, &st->depth_m, &err);
	if (!r && paths->cloud)
		r = dao_ply_write(paths->cloud, cam, o->cloud_filtered ? &st->depth_m : depth,
				  &st->ao, NULL, &err);
	if (r) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	return process_mcap_write(st, depth, shaded_path != NULL, index);
}

static int process_one(const struct process_options *o, struct run_state *st, const char *in,
		       const struct process_paths *paths, uint64_t index)
{
	struct dao_error err;
	struct dao_frame depth;
	if (dao_png_read_depth_limited(in, (float)o->depth_unit, o->max_pixels, &depth, &err)) {
		process_print_error(&err);
		return 1;
	}
	int r = process_depth(o, st, &depth, NULL, paths, index);
	dao_frame_free(&depth);
	return r;
}

/* Size of the first image, to set up the camera. */
static int probe_size(const char *path, uint64_t max_pixels, uint32_t *w, uint32_t *h)
{
	struct dao_frame f;
	struct dao_error err;
	if (dao_png_read_limited(path, max_pixels, &f, &err)) {
		process_print_error(&err);
		return 1;
	}
	*w = f.width;
	*h = f.height;
	dao_frame_free(&f);
	return 0;
}

/*
 * The PNGs of a directory input (into files) and the output directories:
 * 0, or the exit status (files freed).
 */
static int prepare_outputs(const struct process_options *o, int is_dir, struct file_list *files)
{
	int status;
	if (is_dir) {
		int r = file_list_pngs(o->input, files);
		if (r) {
			fprintf(stderr, "depthao: cannot list '%s': %s\n", o->input, strerror(-r));
			return 1;
		}
		if (files->count == 0) {
			fprintf(stderr, "depthao: no *.png files in '%s'\n", o->input);
			return 1;
		}
		if ((status = process_check_cloud_frames(o, files->count, 0))) {
			file_list_free(files);
			return status;
		}
		if ((o->ao_out && process_ensure_dir(o->ao_out)) ||
		    (o->shaded_out && process_ensure_dir(o->shaded_out)) ||
		    (o->depth_out && process_ensure_dir(o->depth_out))) {
			file_list_free(files);
			return 1;
		}
	}
	if (o->cloud_out && !process_cloud_is_file(o) && process_ensure_dir(o->cloud_out)) {
		file_list_free(files);
		return 1;
	}
	return 0;
}

/* The context and output frames for the size of the first input: 0 or the exit status. */
static int open_run(const struct process_options *o, int is_dir, const struct file_list *files,
		    struct run_state *st)
{
	char *first = is_dir ? path_join(o->input, files->names[0]) : strdup(o->input);
	uint32_t w = 0, h = 0;
	struct dao_camera cam;
	struct dao_error err;
	int status = !first ? 1 : probe_size(first, o->max_pixels, &w, &h);
	free(first);
	if (!status)
		status = process_resolve_camera(o, w, h, NULL, &cam);
	if (!status && (dao_context_create(&st->ctx, &cam, &o->params, &err) ||
			dao_frame_alloc(&st->ao, DAO_PIXFMT_GRAY16, w, h, &err) ||
			dao_frame_alloc(&st->rgb, DAO_PIXFMT_RGB24, w, h, &err) ||
			process_alloc_depth_outputs(o, st, w, h, &err))) {
		fprintf(stderr, "depthao: %s\n", err.message);
		status = 1;
	}
	if (!status)
		status = process_mcap_open(o, st, &cam, 0);
	if (!status)
		status = process_pose_open(o, st);
	return status;
}

/* One PNG input: the exit status. */
static int process_file(const struct process_options *o, struct run_state *st)
{
	char *cloud = o->cloud_out && !process_cloud_is_file(o)
			      ? process_cloud_name(o->cloud_out, o->input) : NULL;
	struct process_paths out = { o->ao_out, o->shaded_out, NULL, cloud ? cloud : o->cloud_out,
				     o->depth_out };
	int status = process_one(o, st, o->input, &out, o->frame_index);
	free(cloud);
	return status;
}

/* --poses: the trajectory and the frames' rate (for names that are not times) */
struct run_poses {
	struct poses_file pf;
	double fps;
	size_t missing; /* frames the file had no pose for */
};

/* The trajectory and camera.json's fps (default 30): 0 or the exit status. */
static int load_poses(const struct process_options *o, struct run_poses *rp)
{
	struct dao_error err;
	if (poses_file_read(o->poses, &rp->pf, &err)) {
		fprintf(stderr, "depthao: --poses: %s\n", err.message);
		return 1;
	}
	rp->fps = 30.0;
	char *cj = path_join(o->input, "camera.json");
	struct json_object *root = cj ? json_object_from_file(cj) : NULL, *v;
	if (root && json_object_object_get_ex(root, "fps", &v)) {
		const double f = json_object_get_double(v);
		if (f > 0.0 && f <= 1e6)
			rp->fps = f;
	}
	json_object_put(root);
	free(cj);
	return 0;
}

/* The pose of frame i (file `name`) for the context, or none where the file has none. */
static int give_pose(struct run_state *st, struct run_poses *rp, const char *name, size_t i)
{
	double t, q[4], p[3];
	if (!poses_name_time(name, &t))
		t = (double)i / rp->fps;
	const int have = poses_file_at(&rp->pf, t, q, p);
	rp->missing += !have;
	struct dao_error err;
	if (dao_context_set_pose(st->ctx, have ? q : NULL, p, &err)) {
		fprintf(stderr, "depthao: frame %s: %s\n", name, err.message);
		return 1;
	}
	return 0;
}

/* Every PNG of a directory, in name order, with a progress bar: the exit status. */
static int process_files(const struct process_options *o, struct run_state *st,
			 const struct file_list *files, struct run_poses *rp)
{
	struct progress bar;
	int status = 0;
	progress_begin(&bar, files->count, o->quiet);
	for (size_t i = 0; i < files->count && !status; i++) {
		char *in = path_join(o->input, files->names[i]);
		char *ao = o->ao_out ? path_join(o->ao_out, files->names[i]) : NULL;
		char *sh = o->shaded_out ? path_join(o->shaded_out, files->names[i]) : NULL;
		char *dp = o->depth_out ? path_join(o->depth_out, files->names[i]) : NULL;
		char *pc = o->cloud_out ? (process_cloud_is_file(o)
						   ? strdup(o->cloud_out)
						   : process_cloud_name(o->cloud_out, files->names[i]))
				       : NULL;
		if (!in || (o->ao_out && !ao) || (o->shaded_out && !sh) || (o->cloud_out && !pc) ||
		    (o->depth_out && !dp)) {
			fprintf(stderr, "depthao: out of memory\n");
			status = 1;
		} else {
			struct process_paths out = { ao, sh, NULL, pc, dp };
			status = o->poses ? give_pose(st, rp, files->names[i], i) : 0;
			if (!status)
				status = process_one(o, st, in, &out, o->frame_index + i);
		}
		free(in);
		free(ao);
		free(sh);
		free(pc);
		free(dp);
		progress_update(&bar, i + 1, st->ms_total / (double)(st->frames ? st->frames : 1));
	}
	progress_end(&bar);
	return status;
}

int cmd_process(int argc, char **argv)
{
	struct process_options o;
	int status = parse_args(argc, argv, &o);
	if (status)
		return status;

	if (process_input_is_stream(o.input))
		return process_stream(&o);
	if (o.start || o.max_frames)
		return usage_error("process", "--start and --frames apply to recordings and devices, "
				   "not to PNG input");
	int is_dir = path_is_dir(o.input);
	if (is_dir < 0) {
		fprintf(stderr, "depthao: cannot read input '%s': %s\n", o.input, strerror(-is_dir));
		return 1;
	}
	struct file_list files = { 0 };
	if ((status = prepare_outputs(&o, is_dir, &files)))
		return status;
	struct run_state st = { 0 };
	struct run_poses rp = { 0 };
	if (o.poses && !is_dir)
		status = usage_error("process", "--poses needs a directory of PNG frames");
	if (!status && o.poses)
		status = load_poses(&o, &rp);
	if (!status)
		status = open_run(&o, is_dir, &files, &st);
	if (!status)
		status = is_dir ? process_files(&o, &st, &files, &rp) : process_file(&o, &st);
	if (!status && o.poses && rp.missing)
		fprintf(stderr, "depthao: %s had no pose for %zu of %zu frames (filtered without "
			"motion)\n", o.poses, rp.missing, files.count);
	poses_file_free(&rp.pf);
	if (!status && !o.quiet)
		process_print_summary(&o, &st); /* no overlay from PNG input */
	status = process_mcap_close(&st, status);
	status = process_pose_close(&o, &st, status);
	process_free_outputs(&st);
	dao_context_destroy(st.ctx);
	file_list_free(&files);
	return status;
}
