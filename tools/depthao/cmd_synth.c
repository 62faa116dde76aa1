/* SPDX-License-Identifier: MIT */
/*
 * depthao synth: analytic scenes rendered exactly, with ground-truth AO.
 * For each scene it writes DIR/NAME/ (DIR/NAME-noisy/ with Gaussian noise,
 * DIR/NAME-SENSOR/ as another simulated sensor delivers it): depth.png
 * (16-bit millimetres), ao_gt.png (16-bit visibility, round(v x 65535)) and
 * camera.json (Open3D intrinsics format).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <json-c/json.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "common/camera_file.h"
#include "commands.h"
#include "file_list.h"
#include "synth/suite.h"
#include "synth_motion.h"

/* Sets an out-of-memory error and returns 1 (for expressions). */
static int set_oom(struct dao_error *err)
{
	snprintf(err->message, sizeof err->message, "out of memory");
	err->code = -ENOMEM;
	return 1;
}

/* Frame rate of synthetic sequences and their .oni recordings unless --fps says. */
#define SYNTH_ONI_FPS 30

struct synth_options {
	const char *scene, *out;
	enum synth_sensor sensor;
	int sensor_given, variant, rays_sqrt, frames;
	int oni;                 /* also write NAME.oni */
	enum dao_oni_codec codec;
	double radius;
	unsigned long long seed;
	const char *trajectory;  /* a moving camera (synth_motion.h), or NULL */
	int frames_given, moving;
	double fps;
	struct synth_trajectory tr;
};

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao synth --scene NAME|all --out DIR [options]\n"
		"\n"
		"Renders a synthetic scene (640x480, fx = fy = 525, cx = 319.5, cy = 239.5) with\n"
		"ray-traced ground-truth ambient occlusion: cosine-weighted hemisphere visibility\n"
		"around the true normal, rays blocked by geometry closer than the radius.\n"
		"Writes DIR/NAME/{depth.png, ao_gt.png, camera.json}.\n"
		"\n"
		"  --scene NAME   one of:");
	for (const char *const *n = synth_scene_names(); *n; n++)
		fprintf(out, " %s", *n);
	fprintf(out,
		", or all (every scene, clean and noisy)\n"
		"  --out DIR      output directory (created if missing)\n"
		"  --sensor MODEL what a sensor delivers (the ground truth stays exact):\n"
		"                 clean (default), gaussian (sigma = 0.0012 z^2 m, mm steps, ~2%%\n"
		"                 holes; to DIR/NAME-noisy), structured-light (Kinect v1 /\n"
		"                 PrimeSense: dot pattern, 9x9 block matching, 1/8-px disparity,\n"
		"                 projector shadows), active-stereo (RealSense D4xx: two IR\n"
		"                 cameras, 5 cm apart), tof (time of flight: flying pixels,\n"
		"                 multipath, amplitude noise); to DIR/NAME-MODEL\n"
		"  --noise        the same as --sensor gaussian\n"
		"  --seed N       noise seed (default 1); frame i of a sequence uses N + i, the\n"
		"                 device's own error (structured light's drift) N in every frame\n"
		"  --variant N    a perturbed variant of the scene (camera, objects, walls; 0 = the\n"
		"                 scene itself; eval's held-out family uses the odd ones)\n"
		"  --rays N       ground-truth rays per pixel, a perfect square (default 256)\n"
		"  --radius R     AO radius in metres (default 0.5)\n"
		"  --frames N     a sequence of N frames with the scene's object moving, written as\n"
		"                 DIR/NAME/depth/NNNN.png (+ camera.json) and DIR/NAME/ao_gt/NNNN.png\n"
		"  --trajectory T a moving camera: %s;\n"
		"                 a sequence (--frames, default 16) of the still scene (its object\n"
		"                 moves with --moving) written as DIR/NAME-T[-MODEL]/ with\n"
		"                 depth/, ao_gt/, depth_gt/ (the true depth, mm) and poses.txt (the\n"
		"                 true pose per frame, TUM: timestamp tx ty tz qx qy qz qw);\n"
		"                 odd --variant numbers are the held-out family (docs/motion.md)\n"
		"  --fps N        frame rate of a sequence and its .oni, 1..240 (default 30)\n"
		"  --moving       with --trajectory: the scene's object moves too (plane,\n"
		"                 room-corner, stairs and boxes have none)\n"
		"  --oni CODEC    also write the depth sequence as DIR/NAME.oni (--fps, 1 mm,\n"
		"                 the camera's field of view) with codec none, 16z or 16zt\n"
		"  --help         this text\n", synth_trajectory_names());
}

static int check_args(struct synth_options *o);

static int parse_args(int argc, char **argv, struct synth_options *o)
{
	*o = (struct synth_options){ .rays_sqrt = 16, .radius = 0.5, .seed = 1, .frames = 1,
				     .fps = SYNTH_ONI_FPS };
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			usage(stdout);
			exit(0);
		}
		if (strcmp(a, "--noise") == 0) {
			o->sensor = SYNTH_SENSOR_GAUSSIAN;
			o->sensor_given = 1;
			continue;
		}
		if (strcmp(a, "--moving") == 0) {
			o->moving = 1;
			continue;
		}
		const char *names[] = { "--scene", "--out", "--seed", "--rays", "--radius", "--frames",
					 "--oni", "--sensor", "--variant", "--trajectory", "--fps" };
		size_t k;
		for (k = 0; k < 11 && strcmp(a, names[k]) != 0; k++)
			;
		if (k == 11)
			return usage_error("synth", "unknown option '%s'", a);
		if (i + 1 >= argc)
			return usage_error("synth", "%s needs a value", a);
		const char *v = argv[++i];
		char *end;
		errno = 0;
		switch (k) {
		case 0: o->scene = v; break;
		case 1: o->out = v; break;
		case 2:
			o->seed = strtoull(v, &end, 10);
			if (*end || !*v || errno || v[0] == '-')
				return usage_error("synth", "--seed '%s' is not a non-negative integer", v);
			break;
		case 3: {
			long n = strtol(v, &end, 10);
			long r = lrint(sqrt((double)(n > 0 ? n : 0)));
			if (*end || !*v || n < 1 || n > 65536 || r * r != n)
				return usage_error("synth", "--rays '%s' must be a perfect square in 1..65536", v);
			o->rays_sqrt = (int)r;
			break;
		}
		case 4:
			o->radius = strtod(v, &end);
			if (*end || !*v || !(o->radius > 0.0 && o->radius <= 100.0))
				return usage_error("synth", "--radius '%s' must be a number in (0, 100] metres", v);
			break;
		case 5: {
			long n = strtol(v, &end, 10);
			if (*end || !*v || n < 1 || n > 10000)
				return usage_error("synth", "--frames '%s' must be an integer in 1..10000", v);
			o->frames = (int)n;
			o->frames_given = 1;
			break;
		}
		case 6:
			if (dao_oni_codec_from_name(v, &o->codec))
				return usage_error("synth", "--oni '%s' must be none, 16z or 16zt", v);
			o->oni = 1;
			break;
		case 7: {
			struct dao_error err;
			if (synth_sensor_parse(v, &o->sensor, &err))
				return usage_error("synth", "%s", err.message);
			o->sensor_given = 1;
			break;
		}
		case 8: {
			long n = strtol(v, &end, 10);
			if (*end || !*v || n < 0 || n > 1000000)
				return usage_error("synth", "--variant '%s' must be an integer in 0..1000000", v);
			o->variant = (int)n;
			break;
		}
		case 9: o->trajectory = v; break;
		case 10:
			o->fps = (double)strtol(v, &end, 10);
			if (*end || !*v || !(o->fps >= 1.0 && o->fps <= 240.0))
				return usage_error("synth", "--fps '%s' must be an integer in 1..240", v);
			break;
		}
	}
	return check_args(o);
}

/* What the options say together; 0 or the usage error's status. */
static int check_args(struct synth_options *o)
{
	if (!o->scene)
		return usage_error("synth", "--scene is required");
	if (!o->out)
		return usage_error("synth", "--out is required");
	if ((o->frames > 1 || o->oni || o->trajectory) && strcmp(o->scene, "all") == 0)
		return usage_error("synth", "--frames, --oni and --trajectory need a single --scene");
	if (o->moving && !o->trajectory)
		return usage_error("synth", "--moving needs --trajectory (without one, --frames moves "
				   "the object)");
	if (strcmp(o->scene, "all") != 0) {
		struct synth_scene s;
		struct dao_error err;
		if (synth_scene_build_variant(o->scene, 0.0, o->variant, &s, &err))
			return usage_error("synth", "%s", err.message);
		if (o->trajectory &&
		    synth_trajectory_init(&o->tr, o->trajectory, &s,
					  synth_motion_seed(o->seed, o->variant), &err))
			return usage_error("synth", "%s", err.message);
	}
	if (o->trajectory && !o->frames_given)
		o->frames = 16;
	if (o->trajectory) /* stop and start change at the middle frame */
		synth_trajectory_set_length(&o->tr, o->frames, o->fps);
	return 0;
}

static int make_dir(const char *path)
{
	if (mkdir(path, 0777) == 0 || errno == EEXIST) {
		if (path_is_dir(path) == 1)
			return 0;
		fprintf(stderr, "depthao: '%s' exists and is not a directory\n", path);
		return 1;
	}
	fprintf(stderr, "depthao: cannot create directory '%s': %s\n", path, strerror(errno));
	return 1;
}

/* DIR/NAME, DIR/NAME-noisy (Gaussian) or DIR/NAME-SENSOR. */
static void case_dir_name(char *name, size_t len, const char *scene, enum synth_sensor sensor)
{
	if (sensor == SYNTH_SENSOR_CLEAN)
		snprintf(name, len, "%s", scene);
	else if (sensor == SYNTH_SENSOR_GAUSSIAN)
		snprintf(name, len, "%s-noisy", scene);
	else
		snprintf(name, len, "%s-%s", scene, synth_sensor_name(sensor));
}

static int write_case(const struct synth_options *o, const struct synth_suite *suite,
		      const struct synth_case *c)
{
	char name[128];
	case_dir_name(name, sizeof name, c->scene, c->sensor);
	char *dir = path_join(o->out, name);
	char *depth_path = dir ? path_join(dir, "depth.png") : NULL;
	char *gt_path = dir ? path_join(dir, "ao_gt.png") : NULL;
	char *cam_path = dir ? path_join(dir, "camera.json") : NULL;
	const uint32_t w = suite->cam.width, h = suite->cam.height;
	struct dao_frame gt = { 0 };
	struct dao_error err;
	char msg[512];
	int status = 1;
	if (!cam_path || make_dir(dir))
		goto out;
	struct dao_frame depth = {
		.format = DAO_PIXFMT_DEPTH16, .width = w, .height = h,
		.stride = (int32_t)(2 * w), .data = c->depth_mm, .depth_unit = 0.001f,
	};
	if (dao_frame_alloc(&gt, DAO_PIXFMT_GRAY16, w, h, &err))
		goto fail;
	for (size_t i = 0; i < (size_t)w * h; i++)
		((uint16_t *)gt.data)[i] = (uint16_t)lrintf(c->gt[i] * 65535.0f);
	if (dao_png_write(depth_path, &depth, &err) || dao_png_write(gt_path, &gt, &err))
		goto fail;
	struct json_object *extra = json_object_new_object();
	json_object_object_add(extra, "depth_unit", json_object_new_double(0.001));
	json_object_object_add(extra, "scene", json_object_new_string(c->scene));
	json_object_object_add(extra, "variant", json_object_new_int(c->variant));
	json_object_object_add(extra, "sensor", json_object_new_string(synth_sensor_name(c->sensor)));
	json_object_object_add(extra, "seed", json_object_new_uint64(o->seed));
	json_object_object_add(extra, "noise", json_object_new_boolean(c->noisy));
	json_object_object_add(extra, "radius", json_object_new_double(o->radius));
	json_object_object_add(extra, "rays", json_object_new_int(o->rays_sqrt * o->rays_sqrt));
	int r = camera_file_write(cam_path, &suite->cam, extra, msg, sizeof msg);
	json_object_put(extra);
	if (r) {
		fprintf(stderr, "depthao: %s\n", msg);
		goto out;
	}
	printf("%s: %s\n", dir, c->sensor == SYNTH_SENSOR_GAUSSIAN ? "noisy" : synth_sensor_name(c->sensor));
	status = 0;
	goto out;
fail:
	fprintf(stderr, "depthao: %s\n", err.message);
out:
	dao_frame_free(&gt);
	free(dir);
	free(depth_path);
	free(gt_path);
	free(cam_path);
	return status;
}

/* BASE.oni, the sequence's recording beside its directory; 1 on failure (reported). */
static int open_sequence_oni(const struct synth_options *o, const struct dao_camera *cam,
			     const char *base, char **oni_path, struct dao_oni_writer **oni)
{
	struct dao_error err;
	size_t n = strlen(base);
	struct dao_oni_writer_options wo = {
		.size = sizeof(struct dao_oni_writer_options),
		.width = cam->width, .height = cam->height, .fps = (uint32_t)o->fps,
		.codec = o->codec, .pixel_format = DAO_ONI_PIXEL_DEPTH_1_MM,
		.overwrite = 1, /* made again, like the PNGs beside it */
	};
	dao_camera_fov(cam, &wo.hfov, &wo.vfov);
	if (!(*oni_path = malloc(n + 5)))
		return 1;
	memcpy(*oni_path, base, n);
	memcpy(*oni_path + n, ".oni", 5);
	if (dao_oni_writer_open(*oni_path, &wo, oni, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	return 0;
}

/* Frame i: rendered, simulated, written as PNGs (and to the recording); 1 on failure. */
static int write_sequence_frame(const struct synth_options *o, const struct dao_camera *cam, int i,
				const char *ddir, const char *gdir, const char *tdir,
				struct dao_oni_writer *oni)
{
	struct synth_scene scene;
	struct synth_image img;
	struct synth_case c = { 0 };
	struct dao_frame gt = { 0 };
	struct dao_error err;
	char file[32];
	double t = o->frames > 1 ? (double)i / (double)(o->frames - 1) : 0.0;
	if (o->trajectory && !o->moving)
		t = 0.0;
	int r = synth_scene_build_variant(o->scene, t, o->variant, &scene, &err);
	if (!r && o->trajectory) {
		struct synth_pose pose;
		synth_trajectory_pose(&o->tr, (double)i / o->fps, &pose);
		synth_scene_view_from(&scene, &pose);
	}
	if (!r)
		r = synth_render(&scene, cam, o->radius, o->rays_sqrt, 2, &img, &err);
	if (!r && o->trajectory)
		r = synth_motion_write_depth_gt(tdir, i, &img, &err);
	if (r) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	/* one device for the whole sequence, new noise in every frame */
	r = synth_case_simulate_frame(&c, &scene, o->variant, cam, &img, o->sensor, o->seed,
				      o->seed + (uint64_t)i, 2, &err);
	if (!r)
		r = dao_frame_alloc(&gt, DAO_PIXFMT_GRAY16, cam->width, cam->height, &err);
	if (!r) {
		for (size_t k = 0; k < (size_t)cam->width * cam->height; k++)
			((uint16_t *)gt.data)[k] = (uint16_t)lrintf(img.gt[k] * 65535.0f);
		struct dao_frame depth = {
			.format = DAO_PIXFMT_DEPTH16, .width = cam->width, .height = cam->height,
			.stride = (int32_t)(2 * cam->width), .data = c.depth_mm, .depth_unit = 0.001f,
		};
		snprintf(file, sizeof file, "%04d.png", i);
		char *dp = path_join(ddir, file), *gp = path_join(gdir, file);
		r = !dp || !gp ? set_oom(&err)
			       : dao_png_write(dp, &depth, &err) || dao_png_write(gp, &gt, &err);
		if (!r && oni)
			r = dao_oni_writer_write_depth(oni, &depth,
						       (uint64_t)i * 1000000u / (uint64_t)o->fps,
						       &err) != 0;
		free(dp);
		free(gp);
	}
	dao_frame_free(&gt);
	synth_case_free(&c);
	synth_image_free(&img);
	if (r) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	return 0;
}

/* The sequence's camera.json, with what made it; 1 on failure (reported). */
static int write_sequence_camera(const struct synth_options *o, const struct dao_camera *cam,
				 const char *cam_path)
{
	char msg[512];
	struct json_object *extra = json_object_new_object();
	json_object_object_add(extra, "depth_unit", json_object_new_double(0.001));
	json_object_object_add(extra, "scene", json_object_new_string(o->scene));
	json_object_object_add(extra, "variant", json_object_new_int(o->variant));
	json_object_object_add(extra, "sensor", json_object_new_string(synth_sensor_name(o->sensor)));
	json_object_object_add(extra, "seed", json_object_new_uint64(o->seed));
	json_object_object_add(extra, "noise", json_object_new_boolean(o->sensor != SYNTH_SENSOR_CLEAN));
	json_object_object_add(extra, "frames", json_object_new_int(o->frames));
	if (o->trajectory) {
		json_object_object_add(extra, "trajectory", json_object_new_string(o->tr.name));
		json_object_object_add(extra, "fps", json_object_new_double(o->fps));
		json_object_object_add(extra, "moving_object", json_object_new_boolean(o->moving));
		json_object_object_add(extra, "set", json_object_new_string(synth_motion_set(o->variant)));
	}
	int r = camera_file_write(cam_path, cam, extra, msg, sizeof msg);
	json_object_put(extra);
	if (r) {
		fprintf(stderr, "depthao: %s\n", msg);
		return 1;
	}
	return 0;
}

/* A sequence: DIR/NAME/depth/NNNN.png and DIR/NAME/ao_gt/NNNN.png (and DIR/NAME.oni). */
static int write_sequence(const struct synth_options *o)
{
	struct dao_camera cam;
	synth_default_camera(&cam);
	char name[128], scene_traj[96];
	snprintf(scene_traj, sizeof scene_traj, "%s%s%s", o->scene, o->trajectory ? "-" : "",
		 o->trajectory ? o->tr.name : "");
	case_dir_name(name, sizeof name, scene_traj, o->sensor);
	char *base = path_join(o->out, name);
	char *ddir = base ? path_join(base, "depth") : NULL;
	char *gdir = base ? path_join(base, "ao_gt") : NULL;
	char *tdir = base ? path_join(base, "depth_gt") : NULL;
	char *pose_path = base ? path_join(base, "poses.txt") : NULL;
	char *cam_path = ddir ? path_join(ddir, "camera.json") : NULL;
	char *oni_path = NULL;
	struct dao_oni_writer *oni = NULL;
	int status = 1;
	if (!cam_path || !tdir || !pose_path || make_dir(base) || make_dir(ddir) || make_dir(gdir))
		goto out;
	if (o->trajectory && (make_dir(tdir) || synth_motion_write_poses(pose_path, &o->tr, o->frames,
									 o->fps, o->scene, o->variant)))
		goto out;
	if (o->oni && open_sequence_oni(o, &cam, base, &oni_path, &oni))
		goto out;
	for (int i = 0; i < o->frames; i++)
		if (write_sequence_frame(o, &cam, i, ddir, gdir, tdir, oni))
			goto out;
	if (write_sequence_camera(o, &cam, cam_path))
		goto out;
	if (oni) {
		struct dao_error err;
		struct dao_oni_writer *w = oni;
		oni = NULL;
		if (dao_oni_writer_finish(w, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			goto out;
		}
		printf("%s: %d frames, codec %s\n", oni_path, o->frames, dao_oni_codec_name(o->codec));
	}
	printf("%s: %d frames (%s)\n", base, o->frames,
	       o->sensor == SYNTH_SENSOR_GAUSSIAN ? "noisy" : synth_sensor_name(o->sensor));
	status = 0;
out:
	dao_oni_writer_abort(oni);
	free(oni_path);
	free(base);
	free(ddir);
	free(gdir);
	free(tdir);
	free(pose_path);
	free(cam_path);
	return status;
}

int cmd_synth(int argc, char **argv)
{
	struct synth_options o;
	int status = parse_args(argc, argv, &o);
	if (status)
		return status;
	if (make_dir(o.out))
		return 1;
	if (o.frames > 1 || o.oni || o.trajectory)
		return write_sequence(&o);
	int all = strcmp(o.scene, "all") == 0;
	const char *one[2] = { o.scene, NULL };
	/* every scene: clean and Gaussian unless a sensor is named; one scene: that sensor */
	enum synth_sensor sensors[2] = { SYNTH_SENSOR_CLEAN, SYNTH_SENSOR_GAUSSIAN };
	int nsensors = 2;
	if (o.sensor_given || !all) {
		sensors[0] = o.sensor;
		nsensors = 1;
	}
	const struct synth_suite_spec spec = {
		.scenes = all ? NULL : one, .radius = o.radius, .rays_sqrt = o.rays_sqrt,
		.sensors = sensors, .nsensors = nsensors, .variant_first = o.variant,
		.variant_step = 1, .variants = 1, .seed = o.seed, .threads = 2,
	};
	struct synth_suite suite;
	struct dao_error err;
	if (synth_suite_load_spec(&suite, &spec, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	for (int i = 0; i < suite.count && !status; i++)
		status = write_case(&o, &suite, &suite.cases[i]);
	synth_suite_free(&suite);
	return status;
}
