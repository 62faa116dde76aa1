/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

#include <depthao/frame.h>

#include "common/camera_info_yaml.h"

struct parse {
	yaml_document_t *doc;
	const char *name;
	char *msg;
	size_t len;
};

__attribute__((format(printf, 2, 3))) static int fail(struct parse *ps, const char *fmt, ...)
{
	char what[320];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(what, sizeof what, fmt, ap);
	va_end(ap);
	snprintf(ps->msg, ps->len, "camera file '%s': %s", ps->name, what);
	return -1;
}

/* The value of `key` in a mapping node, or NULL. */
static yaml_node_t *lookup(struct parse *ps, yaml_node_t *map, const char *key)
{
	for (yaml_node_pair_t *pr = map->data.mapping.pairs.start; pr < map->data.mapping.pairs.top;
	     pr++) {
		yaml_node_t *k = yaml_document_get_node(ps->doc, pr->key);
		if (k && k->type == YAML_SCALAR_NODE &&
		    k->data.scalar.length == strlen(key) &&
		    !memcmp(k->data.scalar.value, key, k->data.scalar.length))
			return yaml_document_get_node(ps->doc, pr->value);
	}
	return NULL;
}

/* A scalar node's text (NUL-terminated by libyaml). */
static const char *scalar(yaml_node_t *n)
{
	return n && n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : NULL;
}

static int to_double(const char *s, double *out)
{
	char *end;
	if (!s || !*s)
		return -1;
	double v = strtod(s, &end);
	while (*end == ' ')
		end++;
	if (*end || !isfinite(v))
		return -1;
	*out = v;
	return 0;
}

static int get_count(struct parse *ps, yaml_node_t *map, const char *where, const char *key,
		     long max, long *out)
{
	yaml_node_t *n = lookup(ps, map, key);
	const char *s = scalar(n);
	char *end;
	if (!n)
		return fail(ps, "%s%s%s is missing", where, *where ? "." : "", key);
	long v = s ? strtol(s, &end, 10) : 0;
	if (!s || !*s || *end || v < 1 || v > max)
		return fail(ps, "%s%s%s must be an integer in 1..%ld, not '%.40s'", where,
			    *where ? "." : "", key, max, s ? s : "(not a scalar)");
	*out = v;
	return 0;
}

/* A matrix {rows, cols, data}: rows x cols must be the data's length and, if
 * given, want_rows x want_cols; fills out[0..n). */
static int get_matrix(struct parse *ps, yaml_node_t *root, const char *key, long want_rows,
		      long want_cols, long max, double *out, int *n_out)
{
	yaml_node_t *m = lookup(ps, root, key);
	if (!m)
		return fail(ps, "%s is missing (a mapping with rows, cols and data)", key);
	if (m->type != YAML_MAPPING_NODE)
		return fail(ps, "%s must be a mapping with rows, cols and data", key);
	long rows, cols;
	if (get_count(ps, m, key, "rows", max, &rows) || get_count(ps, m, key, "cols", max, &cols))
		return -1;
	if ((want_rows && rows != want_rows) || (want_cols && cols != want_cols))
		return fail(ps, "%s is %ldx%ld, it must be %ldx%ld", key, rows, cols,
			    want_rows ? want_rows : rows, want_cols ? want_cols : cols);
	yaml_node_t *data = lookup(ps, m, "data");
	if (!data || data->type != YAML_SEQUENCE_NODE)
		return fail(ps, "%s.data must be a list of %ld numbers", key, rows * cols);
	long count = data->data.sequence.items.top - data->data.sequence.items.start;
	if (count != rows * cols || count > max)
		return fail(ps, "%s.data has %ld numbers, rows x cols = %ld x %ld needs %ld", key, count,
			    rows, cols, rows * cols);
	for (long i = 0; i < count; i++) {
		yaml_node_t *v = yaml_document_get_node(ps->doc, data->data.sequence.items.start[i]);
		if (to_double(scalar(v), &out[i]))
			return fail(ps, "%s.data[%ld] is not a finite number ('%.40s')", key, i,
				    scalar(v) ? scalar(v) : "(not a scalar)");
	}
	*n_out = (int)count;
	return 0;
}

static int get_size(struct parse *ps, yaml_node_t *root, const char *key, uint32_t *out)
{
	long v;
	if (get_count(ps, root, "", key, DAO_MAX_DIMENSION, &v))
		return -1;
	*out = (uint32_t)v;
	return 0;
}

static int get_text(struct parse *ps, yaml_node_t *root, const char *key, char *out, size_t len)
{
	yaml_node_t *n = lookup(ps, root, key);
	out[0] = '\0';
	if (!n)
		return 0;
	const char *s = scalar(n);
	if (!s || strlen(s) >= len)
		return fail(ps, "%s must be a text of at most %zu characters", key, len - 1);
	memcpy(out, s, strlen(s) + 1);
	return 0;
}

/* A CameraInfo's mappings hold a handful of keys. */
#define MAX_MAPPING_KEYS 64

/* Every mapping of the document: scalar keys only, each once (YAML forbids
 * duplicates; a parser that took the first or the last would silently pick). */
static int check_keys(struct parse *ps)
{
	for (yaml_node_t *n = ps->doc->nodes.start; n < ps->doc->nodes.top; n++) {
		if (n->type != YAML_MAPPING_NODE)
			continue;
		yaml_node_pair_t *a = n->data.mapping.pairs.start, *top = n->data.mapping.pairs.top;
		if (top - a > MAX_MAPPING_KEYS)
			return fail(ps, "a mapping at line %zu has %ld keys, more than a CameraInfo "
				    "has (%d)", n->start_mark.line + 1, (long)(top - a),
				    MAX_MAPPING_KEYS);
		for (; a < top; a++) {
			yaml_node_t *ka = yaml_document_get_node(ps->doc, a->key);
			if (!ka || ka->type != YAML_SCALAR_NODE)
				return fail(ps, "a key at line %zu is not a plain name",
					    ka ? ka->start_mark.line + 1 : n->start_mark.line + 1);
			for (yaml_node_pair_t *b = a + 1; b < top; b++) {
				yaml_node_t *kb = yaml_document_get_node(ps->doc, b->key);
				if (kb && kb->type == YAML_SCALAR_NODE &&
				    kb->data.scalar.length == ka->data.scalar.length &&
				    !memcmp(kb->data.scalar.value, ka->data.scalar.value,
					    ka->data.scalar.length))
					return fail(ps, "key '%.40s' appears twice (lines %zu and %zu); "
						    "keep one", (const char *)ka->data.scalar.value,
						    ka->start_mark.line + 1, kb->start_mark.line + 1);
			}
		}
	}
	return 0;
}

static int read_document(struct parse *ps, struct camera_info *ci)
{
	yaml_node_t *root = yaml_document_get_root_node(ps->doc);
	if (!root)
		return fail(ps, "is empty");
	if (root->type != YAML_MAPPING_NODE)
		return fail(ps, "is not a ROS CameraInfo (a YAML mapping with image_width, "
			    "image_height, camera_matrix, ...)");
	int n;
	memset(ci, 0, sizeof *ci);
	if (get_size(ps, root, "image_width", &ci->width) ||
	    get_size(ps, root, "image_height", &ci->height) ||
	    get_text(ps, root, "camera_name", ci->name, sizeof ci->name) ||
	    get_text(ps, root, "distortion_model", ci->distortion_model,
		     sizeof ci->distortion_model) ||
	    get_matrix(ps, root, "camera_matrix", 3, 3, 9, ci->k, &n))
		return -1;
	if (ci->k[3] != 0 || ci->k[6] != 0 || ci->k[7] != 0 || ci->k[8] != 1)
		return fail(ps, "camera_matrix's last row is %g %g %g and K[1][0] is %g: a pinhole K "
			    "has 0, 0, 1 and 0 there", ci->k[6], ci->k[7], ci->k[8], ci->k[3]);
	if (lookup(ps, root, "distortion_coefficients") &&
	    get_matrix(ps, root, "distortion_coefficients", 1, 0, CAMERA_INFO_MAX_DISTORTION, ci->d,
		       &ci->nd))
		return -1;
	if (lookup(ps, root, "rectification_matrix")) {
		if (get_matrix(ps, root, "rectification_matrix", 3, 3, 9, ci->r, &n))
			return -1;
		ci->has_r = 1;
	}
	if (lookup(ps, root, "projection_matrix")) {
		if (get_matrix(ps, root, "projection_matrix", 3, 4, 12, ci->p, &n))
			return -1;
		ci->has_p = 1;
	}
	return 0;
}

int camera_info_yaml_parse(const char *text, size_t len, const char *name, struct camera_info *ci,
			   char *msg, size_t msglen)
{
	struct parse ps = { .name = name, .msg = msg, .len = msglen };
	yaml_parser_t parser;
	yaml_document_t doc;
	if (!yaml_parser_initialize(&parser))
		return fail(&ps, "out of memory");
	yaml_parser_set_input_string(&parser, (const unsigned char *)text, len);
	if (!yaml_parser_load(&parser, &doc)) {
		fail(&ps, "not valid YAML: %s%s%s at line %zu, column %zu",
		     parser.problem ? parser.problem : "parse error",
		     parser.context ? " " : "", parser.context ? parser.context : "",
		     parser.problem_mark.line + 1, parser.problem_mark.column + 1);
		yaml_parser_delete(&parser);
		return -1;
	}
	ps.doc = &doc;
	int r = check_keys(&ps);
	if (!r)
		r = read_document(&ps, ci);
	yaml_document_delete(&doc);
	/* one document: another after "---" would be ignored, so it is refused */
	if (!r) {
		yaml_document_t more;
		size_t line = parser.mark.line + 1;
		if (!yaml_parser_load(&parser, &more))
			r = fail(&ps, "not valid YAML after the first document (line %zu): %s; a "
				 "camera file holds one CameraInfo", parser.problem_mark.line + 1,
				 parser.problem ? parser.problem : "parse error");
		else if (yaml_document_get_root_node(&more))
			r = fail(&ps, "has a second YAML document (after line %zu); a camera file "
				 "holds one CameraInfo: remove the rest or split the file", line);
		if (parser.error == YAML_NO_ERROR)
			yaml_document_delete(&more);
	}
	yaml_parser_delete(&parser);
	return r;
}
