/* SPDX-License-Identifier: MIT */
/* Reading TUM trajectory files (trajectory.h): hostile input is checked line by line. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "synth/trajectory.h"

#define LINE_MAX_CHARS 1024
#define FILE_MAX_BYTES (64u << 20)

static int grow(struct synth_pose_list *l, size_t *cap)
{
	size_t n = *cap ? 2 * *cap : 64;
	double *t = realloc(l->time, n * sizeof *t);
	if (!t)
		return -ENOMEM;
	l->time = t;
	struct synth_pose *p = realloc(l->pose, n * sizeof *p);
	if (!p)
		return -ENOMEM;
	l->pose = p;
	*cap = n;
	return 0;
}

/* 1 if the line holds only blanks or is a comment. */
static int blank_or_comment(const char *s)
{
	s += strspn(s, " \t\r");
	return *s == '\0' || *s == '#';
}

/* The 8 numbers of a line; 0, or -EINVAL with a message. */
static int parse_line(char *s, const char *what, size_t lineno, double v[8], struct dao_error *err)
{
	for (int k = 0; k < 8; k++) {
		char *end;
		errno = 0;
		v[k] = strtod(s, &end);
		if (end == s || errno == ERANGE || !isfinite(v[k]))
			return dao_error_set(err, -EINVAL,
					     "%s:%zu: expected 8 finite numbers 'timestamp tx ty tz qx qy "
					     "qz qw', number %d is missing or not finite", what, lineno, k + 1);
		s = end;
	}
	s += strspn(s, " \t\r");
	if (*s)
		return dao_error_set(err, -EINVAL, "%s:%zu: more than 8 numbers on the line", what, lineno);
	double n = sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
	if (!(fabs(n - 1.0) <= 1e-3))
		return dao_error_set(err, -EINVAL,
				     "%s:%zu: the quaternion (%g %g %g %g) has norm %g, not 1: a TUM "
				     "line is 'timestamp tx ty tz qx qy qz qw'", what, lineno, v[4], v[5],
				     v[6], v[7], n);
	return 0;
}

/* Adds one parsed line to the list; 0, or -EINVAL / -ENOMEM with a message. */
static int add_pose(struct synth_pose_list *l, size_t *cap, const double v[8], const char *what,
		    size_t lineno, struct dao_error *err)
{
	if (l->count && !(v[0] > l->time[l->count - 1]))
		return dao_error_set(err, -EINVAL, "%s:%zu: timestamp %.6f does not follow %.6f",
				     what, lineno, v[0], l->time[l->count - 1]);
	if (l->count >= SYNTH_POSES_MAX)
		return dao_error_set(err, -EINVAL, "%s: more than %d poses", what, SYNTH_POSES_MAX);
	if (l->count == *cap && grow(l, cap))
		return dao_error_set(err, -ENOMEM, "%s: out of memory", what);
	l->time[l->count] = v[0];
	struct synth_pose *p = &l->pose[l->count++];
	memcpy(p->t, v + 1, sizeof p->t);
	synth_matrix_from_quat(v + 4, p->R);
	return 0;
}

int synth_poses_parse(const char *text, size_t len, const char *what, struct synth_pose_list *out,
		      struct dao_error *err)
{
	memset(out, 0, sizeof *out);
	size_t cap = 0, lineno = 0, pos = 0;
	char line[LINE_MAX_CHARS + 1];
	int r = 0;
	while (pos < len && !r) {
		const char *nl = memchr(text + pos, '\n', len - pos);
		size_t n = (nl ? (size_t)(nl - text) : len) - pos;
		lineno++;
		if (n > LINE_MAX_CHARS) {
			r = dao_error_set(err, -EINVAL, "%s:%zu: line longer than %d characters", what,
					  lineno, LINE_MAX_CHARS);
			break;
		}
		memcpy(line, text + pos, n);
		line[n] = '\0';
		pos += n + 1;
		if (strlen(line) != n) {
			r = dao_error_set(err, -EINVAL, "%s:%zu: a NUL byte: not a text file", what, lineno);
			break;
		}
		if (blank_or_comment(line))
			continue;
		double v[8];
		r = parse_line(line, what, lineno, v, err);
		if (!r)
			r = add_pose(out, &cap, v, what, lineno, err);
	}
	if (!r && out->count == 0)
		r = dao_error_set(err, -EINVAL, "%s: no poses (a TUM trajectory has lines "
				  "'timestamp tx ty tz qx qy qz qw')", what);
	if (r)
		synth_pose_list_free(out);
	return r;
}

int synth_poses_read(const char *path, struct synth_pose_list *out, struct dao_error *err)
{
	memset(out, 0, sizeof *out);
	FILE *f = fopen(path, "rb");
	if (!f)
		return dao_error_set(err, -errno, "cannot open '%s': %s", path, strerror(errno));
	char *buf = malloc(FILE_MAX_BYTES + 1);
	if (!buf) {
		fclose(f);
		return dao_error_set(err, -ENOMEM, "out of memory reading '%s'", path);
	}
	size_t n = fread(buf, 1, FILE_MAX_BYTES + 1, f);
	int bad = ferror(f);
	fclose(f);
	int r;
	if (bad)
		r = dao_error_set(err, -EIO, "cannot read '%s'", path);
	else if (n > FILE_MAX_BYTES)
		r = dao_error_set(err, -EFBIG, "'%s' is larger than %u MB: not a trajectory", path,
				  FILE_MAX_BYTES >> 20);
	else
		r = synth_poses_parse(buf, n, path, out, err);
	free(buf);
	return r;
}
