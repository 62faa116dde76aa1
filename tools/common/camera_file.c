/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <json-c/json.h>

#include <depthao/frame.h>
#include <depthao/output_file.h>

#include "common/atomic_file.h"
#include "common/camera_file.h"
#include "common/camera_info_yaml.h"

/* A CameraInfo is a few hundred bytes; anything far larger is not one. */
#define CAMERA_FILE_MAX_BYTES (1 << 20)

static int get_number(struct json_object *o, double *out)
{
	if (!o || !(json_object_is_type(o, json_type_double) || json_object_is_type(o, json_type_int)))
		return -1;
	*out = json_object_get_double(o);
	return 0;
}

/* The JSON value of text[0..n), nothing but blanks after it; NULL with a message. */
static struct json_object *parse_json(const char *path, const char *text, size_t n, char *msg,
				      size_t len)
{
	struct json_tokener *tok = json_tokener_new();
	if (!tok || n > INT_MAX) {
		json_tokener_free(tok);
		snprintf(msg, len, "cannot read camera file '%s': out of memory", path);
		return NULL;
	}
	/* trailing characters allowed here to be named below, with their byte */
	json_tokener_set_flags(tok, JSON_TOKENER_STRICT | JSON_TOKENER_ALLOW_TRAILING_CHARS |
				    JSON_TOKENER_VALIDATE_UTF8);
	struct json_object *root = json_tokener_parse_ex(tok, text, (int)n);
	enum json_tokener_error e = json_tokener_get_error(tok);
	size_t end = json_tokener_get_parse_end(tok);
	json_tokener_free(tok);
	if (!root || e != json_tokener_success) {
		snprintf(msg, len, "camera file '%s' is not valid JSON: %s at byte %zu", path,
			 e == json_tokener_continue ? "it ends inside the value"
						    : json_tokener_error_desc(e), end);
		json_object_put(root);
		return NULL;
	}
	for (size_t i = end; i < n; i++)
		if (!strchr(" \t\r\n", text[i]) || !text[i]) {
			unsigned char c = (unsigned char)text[i];
			snprintf(msg, len, "camera file '%s': data after the JSON value at byte %zu "
				 "(%s0x%02x): a camera file holds one JSON object and nothing "
				 "else", path, i, c ? "" : "a NUL byte, ", c);
			json_object_put(root);
			return NULL;
		}
	return root;
}

static int read_json(const char *path, const char *text, size_t n, struct dao_camera *cam,
		     char *msg, size_t len)
{
	struct json_object *root = parse_json(path, text, n, msg, len);
	if (!root)
		return -1;
	int rc = -1;
	struct json_object *w, *h, *k;
	double wd, hd, m[9];
	if (!json_object_object_get_ex(root, "width", &w) || get_number(w, &wd) ||
	    !json_object_object_get_ex(root, "height", &h) || get_number(h, &hd)) {
		snprintf(msg, len, "camera file '%s': needs numeric \"width\" and \"height\"", path);
		goto out;
	}
	if (!json_object_object_get_ex(root, "intrinsic_matrix", &k) ||
	    !json_object_is_type(k, json_type_array) || json_object_array_length(k) != 9) {
		snprintf(msg, len,
			 "camera file '%s': needs \"intrinsic_matrix\", an array of 9 numbers "
			 "(column-major [fx,0,0, 0,fy,0, cx,cy,1])", path);
		goto out;
	}
	for (int i = 0; i < 9; i++)
		if (get_number(json_object_array_get_idx(k, (size_t)i), &m[i])) {
			snprintf(msg, len, "camera file '%s': intrinsic_matrix[%d] is not a number", path, i);
			goto out;
		}
	if (wd < 1 || hd < 1 || wd > DAO_MAX_DIMENSION || hd > DAO_MAX_DIMENSION ||
	    wd != (double)(uint32_t)wd || hd != (double)(uint32_t)hd) {
		snprintf(msg, len, "camera file '%s': size %gx%g is not a valid image size", path, wd, hd);
		goto out;
	}
	struct dao_error err;
	if (dao_camera_from_intrinsics(cam, (uint32_t)wd, (uint32_t)hd, m[0], m[4], m[6], m[7], &err)) {
		snprintf(msg, len, "camera file '%s': %s", path, err.message);
		goto out;
	}
	rc = 0;
out:
	json_object_put(root);
	return rc;
}

int camera_file_write(const char *path, const struct dao_camera *cam, struct json_object *extra,
		      char *msg, size_t len)
{
	struct json_object *root = json_object_new_object();
	struct json_object *k = json_object_new_array();
	const double m[9] = { cam->fx, 0, 0, 0, cam->fy, 0, cam->cx, cam->cy, 1 };
	json_object_object_add(root, "width", json_object_new_int((int)cam->width));
	json_object_object_add(root, "height", json_object_new_int((int)cam->height));
	for (int i = 0; i < 9; i++)
		json_object_array_add(k, json_object_new_double(m[i]));
	json_object_object_add(root, "intrinsic_matrix", k);
	if (extra) {
		json_object_object_foreach(extra, key, val)
			json_object_object_add(root, key, json_object_get(val));
	}
	const char *text = json_object_to_json_string_ext(root, JSON_C_TO_STRING_PRETTY);
	int rc = atomic_write_text(path, text, msg, len);
	json_object_put(root);
	return rc;
}

/* YAML by the name (.yaml, .yml), JSON by the name (.json), else by the first
 * character that is not a blank: '{' is JSON. */
static int is_yaml(const char *path, const char *text, size_t n)
{
	const char *dot = strrchr(path, '.');
	if (dot && (!strcasecmp(dot, ".yaml") || !strcasecmp(dot, ".yml")))
		return 1;
	if (dot && !strcasecmp(dot, ".json"))
		return 0;
	size_t i = 0;
	while (i < n && strchr(" \t\r\n", text[i]))
		i++;
	return i == n || text[i] != '{';
}

static int read_yaml(const char *path, const char *text, size_t n, struct dao_camera *cam,
		     char *warning, size_t wlen, char *msg, size_t len)
{
	struct camera_info ci;
	if (camera_info_yaml_parse(text, n, path, &ci, msg, len))
		return -1;
	/* with distortion, the rectified image's intrinsics (P), as ROS does */
	enum dao_camera_info_matrix from;
	struct dao_error err;
	if (dao_camera_from_camera_info(cam, ci.width, ci.height, ci.k, ci.has_p ? ci.p : NULL, ci.d,
					(size_t)ci.nd, &from, &err)) {
		snprintf(msg, len, "camera file '%s': %s", path, err.message);
		return -1;
	}
	if (warning && wlen)
		warning[0] = '\0';
	if (warning && from != DAO_CAMERA_INFO_K)
		snprintf(warning, wlen,
			 "camera file '%s' has distortion (%s%s%d coefficients): depthao does not "
			 "undistort, so the depth must be rectified (a ROS image_rect topic); using the "
			 "intrinsics of its %s: fx %.3f fy %.3f cx %.3f cy %.3f", path,
			 ci.distortion_model[0] ? ci.distortion_model : "no model",
			 ", ", ci.nd,
			 from == DAO_CAMERA_INFO_P_RECTIFIED ? "projection_matrix (the rectified image's)"
							     : "camera_matrix",
			 cam->fx, cam->fy, cam->cx, cam->cy);
	else if (warning && ci.k[1] != 0)
		snprintf(warning, wlen, "camera file '%s': camera_matrix has skew %g, which "
			 "depthao's pinhole model ignores", path, ci.k[1]);
	return 0;
}

int camera_file_load(const char *path, struct dao_camera *cam, char *warning, size_t wlen,
		     char *msg, size_t len)
{
	if (warning && wlen)
		warning[0] = '\0';
	struct dao_error err;
	int fd = dao_input_file_open(path, "camera file", CAMERA_FILE_MAX_BYTES, NULL, &err);
	FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
	if (!f) {
		if (fd >= 0) {
			snprintf(msg, len, "cannot read camera file '%s': %s", path, strerror(errno));
			close(fd);
		} else {
			snprintf(msg, len, "%s", err.message);
		}
		return -1;
	}
	char *text = malloc(CAMERA_FILE_MAX_BYTES + 1);
	size_t n = text ? fread(text, 1, CAMERA_FILE_MAX_BYTES + 1, f) : 0;
	int bad = !text || ferror(f);
	int e = errno;
	fclose(f);
	int rc = -1;
	if (bad)
		snprintf(msg, len, "cannot read camera file '%s': %s", path,
			 text ? strerror(e) : "out of memory");
	else if (n > CAMERA_FILE_MAX_BYTES)
		snprintf(msg, len, "camera file '%s' is larger than %d bytes: not a camera file",
			 path, CAMERA_FILE_MAX_BYTES);
	else if (is_yaml(path, text, n))
		rc = read_yaml(path, text, n, cam, warning, wlen, msg, len);
	else
		rc = read_json(path, text, n, cam, msg, len);
	free(text);
	return rc;
}

int camera_file_read(const char *path, struct dao_camera *cam, char *msg, size_t len)
{
	char warning[512];
	int r = camera_file_load(path, cam, warning, sizeof warning, msg, len);
	if (!r && warning[0])
		fprintf(stderr, "depthao: warning: %s\n", warning);
	return r;
}

int camera_file_beside(const char *path, char *out, size_t len)
{
	char dir[4096];
	struct stat st;
	if (!path || !*path || snprintf(dir, sizeof dir, "%s", path) >= (int)sizeof dir ||
	    stat(dir, &st) != 0)
		return 0;
	if (!S_ISDIR(st.st_mode)) {
		const size_t n = strlen(dir);
		if (n < 4 || strcasecmp(dir + n - 4, ".png") != 0)
			return 0;
		char *slash = strrchr(dir, '/');
		if (slash == dir)
			dir[1] = '\0'; /* a file in / */
		else if (slash)
			*slash = '\0';
		else
			snprintf(dir, sizeof dir, ".");
	}
	static const char *const names[] = { "camera.json", "camera.yaml" };
	for (int i = 0; i < 2; i++) {
		const int n = snprintf(out, len, "%s%s%s", dir,
				       dir[strlen(dir) - 1] == '/' ? "" : "/", names[i]);
		if (n <= 0 || (size_t)n >= len || access(out, F_OK) != 0)
			continue;
		return access(out, R_OK) == 0 ? 1 : -1;
	}
	return 0;
}
