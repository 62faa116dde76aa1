/* SPDX-License-Identifier: MIT */
#include "poses_file.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Entries at most (a day at 1 kHz is 86 M: this is a file of some GB). */
#define POSES_MAX_ENTRIES 100000000u

void poses_file_free(struct poses_file *pf)
{
	free(pf->t);
	free(pf->pose);
	memset(pf, 0, sizeof *pf);
}

static int grow(struct poses_file *pf, size_t *cap)
{
	if (pf->n < *cap)
		return 0;
	const size_t c = *cap ? 2 * *cap : 256;
	if (c > POSES_MAX_ENTRIES)
		return -1;
	double *t = realloc(pf->t, c * sizeof *t);
	if (t)
		pf->t = t;
	double *p = t ? realloc(pf->pose, c * 7 * sizeof *p) : NULL;
	if (!p)
		return -1;
	pf->pose = p;
	*cap = c;
	return 0;
}

/* One data line into v[8]: 0, or -1 with the reason in msg. */
static int parse_line(const char *s, double v[8], char *msg, size_t len)
{
	for (int k = 0; k < 8; k++) {
		char *end;
		errno = 0;
		v[k] = strtod(s, &end);
		if (end == s || errno == ERANGE || !isfinite(v[k])) {
			snprintf(msg, len, "expected 8 finite numbers (timestamp tx ty tz qx qy qz qw), "
				 "found %d", k);
			return -1;
		}
		s = end;
	}
	s += strspn(s, " \t\r\n");
	if (*s) {
		snprintf(msg, len, "more than 8 values");
		return -1;
	}
	const double n = sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
	if (fabs(n - 1.0) > 1e-3) {
		snprintf(msg, len, "the quaternion qx qy qz qw has norm %g, not 1", n);
		return -1;
	}
	for (int k = 4; k < 8; k++)
		v[k] /= n;
	return 0;
}

static int read_lines(FILE *f, const char *path, struct poses_file *pf, char *msg, size_t len)
{
	char line[1024], why[160];
	size_t cap = 0;
	for (unsigned long no = 1; fgets(line, sizeof line, f); no++) {
		if (!strchr(line, '\n') && !feof(f)) {
			snprintf(msg, len, "%s:%lu: line longer than %zu bytes", path, no,
				 sizeof line - 2);
			return -1;
		}
		const char *s = line + strspn(line, " \t\r\n");
		if (!*s || *s == '#')
			continue;
		double v[8];
		if (parse_line(s, v, why, sizeof why)) {
			snprintf(msg, len, "%s:%lu: %s", path, no, why);
			return -1;
		}
		if (pf->n && !(v[0] > pf->t[pf->n - 1])) {
			snprintf(msg, len, "%s:%lu: timestamp %.6f does not follow %.6f: the poses "
				 "must be in time order", path, no, v[0], pf->t[pf->n - 1]);
			return -1;
		}
		if (grow(pf, &cap)) {
			snprintf(msg, len, "%s: out of memory or more than %u poses", path,
				 POSES_MAX_ENTRIES);
			return -1;
		}
		pf->t[pf->n] = v[0];
		memcpy(pf->pose + 7 * pf->n, v + 1, 7 * sizeof(double));
		pf->n++;
	}
	if (ferror(f)) {
		snprintf(msg, len, "%s: read error", path);
		return -1;
	}
	if (!pf->n) {
		snprintf(msg, len, "%s: no poses (expected lines 'timestamp tx ty tz qx qy qz qw')",
			 path);
		return -1;
	}
	return 0;
}

int poses_file_read(const char *path, struct poses_file *pf, char *msg, size_t len)
{
	memset(pf, 0, sizeof *pf);
	FILE *f = fopen(path, "r");
	if (!f) {
		snprintf(msg, len, "cannot open poses file '%s': %s", path, strerror(errno));
		return -1;
	}
	int r = read_lines(f, path, pf, msg, len);
	fclose(f);
	if (r)
		poses_file_free(pf);
	return r;
}

static void slerp(const double a[4], const double b_in[4], double u, double out[4])
{
	double b[4], d = 0.0;
	for (int k = 0; k < 4; k++)
		d += a[k] * b_in[k];
	const double s = d < 0.0 ? -1.0 : 1.0; /* the shorter way */
	for (int k = 0; k < 4; k++)
		b[k] = s * b_in[k];
	d = fabs(d);
	double wa = 1.0 - u, wb = u;
	if (d < 0.9995) {
		const double th = acos(d), sn = sin(th);
		wa = sin((1.0 - u) * th) / sn;
		wb = sin(u * th) / sn;
	}
	double n = 0.0;
	for (int k = 0; k < 4; k++)
		out[k] = wa * a[k] + wb * b[k], n += out[k] * out[k];
	for (int k = 0; k < 4; k++)
		out[k] /= sqrt(n);
}

int poses_file_at(const struct poses_file *pf, double t, double q[4], double p[3])
{
	if (!pf->n || !isfinite(t))
		return 0;
	/* the last pose at or before t */
	size_t lo = 0, hi = pf->n;
	while (hi - lo > 1) {
		const size_t mid = lo + (hi - lo) / 2;
		if (pf->t[mid] <= t)
			lo = mid;
		else
			hi = mid;
	}
	const double *a = pf->pose + 7 * lo;
	size_t near = lo;
	if (lo + 1 < pf->n && fabs(pf->t[lo + 1] - t) < fabs(pf->t[lo] - t))
		near = lo + 1;
	if (fabs(pf->t[near] - t) <= POSES_EXACT) {
		memcpy(p, pf->pose + 7 * near, 3 * sizeof(double));
		memcpy(q, pf->pose + 7 * near + 3, 4 * sizeof(double));
		return 1;
	}
	if (t < pf->t[0] || lo + 1 >= pf->n || pf->t[lo + 1] - pf->t[lo] > POSES_MAX_GAP)
		return 0;
	const double *b = a + 7, u = (t - pf->t[lo]) / (pf->t[lo + 1] - pf->t[lo]);
	for (int k = 0; k < 3; k++)
		p[k] = a[k] + u * (b[k] - a[k]);
	slerp(a + 3, b + 3, u, q);
	return 1;
}

int poses_name_time(const char *name, double *t)
{
	const char *base = strrchr(name, '/');
	base = base ? base + 1 : name;
	char *end;
	errno = 0;
	const double v = strtod(base, &end);
	/* digits, one '.', digits, then the extension: "1305031102.160407.png" */
	if (end == base || errno || !isfinite(v) || v < 0.0 || *end != '.' ||
	    strchr(base, '.') >= end)
		return 0;
	for (const char *c = base; c < end; c++)
		if (!((*c >= '0' && *c <= '9') || *c == '.'))
			return 0;
	*t = v;
	return 1;
}
