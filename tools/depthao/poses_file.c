/* SPDX-License-Identifier: MIT */
#include "poses_file.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/pose.h>

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
	dao_pose_interpolate(pf->q + 4 * lo, pf->list.pose[lo].t, pf->q + 4 * lo + 4,
			     pf->list.pose[lo + 1].t, u, q, p);
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
