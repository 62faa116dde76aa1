/* SPDX-License-Identifier: MIT */
#include "poses_file.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void poses_file_free(struct poses_file *pf)
{
	synth_pose_list_free(&pf->list);
	free(pf->q);
	memset(pf, 0, sizeof *pf);
}

int poses_file_read(const char *path, struct poses_file *pf, struct dao_error *err)
{
	memset(pf, 0, sizeof *pf);
	int r = synth_poses_read(path, &pf->list, err);
	if (r)
		return r;
	pf->q = malloc(pf->list.count * 4 * sizeof(double));
	if (!pf->q) {
		poses_file_free(pf);
		return dao_error_set(err, -ENOMEM, "out of memory for the poses of '%s'", path);
	}
	for (size_t k = 0; k < pf->list.count; k++)
		synth_quat_from_matrix(pf->list.pose[k].R, pf->q + 4 * k);
	return 0;
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
	const size_t n = pf->list.count;
	const double *ts = pf->list.time;
	if (!n || !isfinite(t))
		return 0;
	/* the last pose at or before t */
	size_t lo = 0, hi = n;
	while (hi - lo > 1) {
		const size_t mid = lo + (hi - lo) / 2;
		if (ts[mid] <= t)
			lo = mid;
		else
			hi = mid;
	}
	size_t near = lo;
	if (lo + 1 < n && fabs(ts[lo + 1] - t) < fabs(ts[lo] - t))
		near = lo + 1;
	if (fabs(ts[near] - t) <= POSES_EXACT) {
		memcpy(p, pf->list.pose[near].t, 3 * sizeof(double));
		memcpy(q, pf->q + 4 * near, 4 * sizeof(double));
		return 1;
	}
	if (t < ts[0] || lo + 1 >= n || ts[lo + 1] - ts[lo] > POSES_MAX_GAP)
		return 0;
	const double u = (t - ts[lo]) / (ts[lo + 1] - ts[lo]);
	const double *a = pf->list.pose[lo].t, *b = pf->list.pose[lo + 1].t;
	for (int k = 0; k < 3; k++)
		p[k] = a[k] + u * (b[k] - a[k]);
	slerp(pf->q + 4 * lo, pf->q + 4 * lo + 4, u, q);
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
