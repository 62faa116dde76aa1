/* SPDX-License-Identifier: MIT */
/*
 * What an AO image says about its depth frame, for the CLI tests on real data:
 *
 *   ao_stats AO.png DEPTH.png UNIT FOCAL [MASK.png]
 *   ao_stats --diff AO.png REF.png
 *
 * AO.png: the 16-bit AO (65535 = open) of `depthao process`; DEPTH.png its
 * 16-bit input (UNIT metres per count, FOCAL pixels).  Prints one line of
 * key=value:
 *   valid      pixels with depth
 *   holes_ok   1 when every pixel without depth is exactly 65535 (the
 *              invalid value) and the AO is the depth's size
 *   mean, p05, p50, p95   AO over the pixels with depth (0..1)
 *   lit        share of them at exactly 1
 *   corr       Pearson correlation over them between 1 - AO and a crude
 *              occlusion estimate from the depth alone: the mean, over 8
 *              directions and 4 distances (3..24 px), of how steeply a
 *              neighbour rises in front of the pixel (elevation's tangent,
 *              clamped to [0, 2]).  A correct AO follows it; an AO of
 *              another place (shifted, transposed) or a constant does not.
 *   open, open_mean, open_dark   with MASK.png (255 = open planar region,
 *              `depthao realcheck --masks-out`): its pixels with depth, the
 *              mean AO there and the share below 0.9
 * --diff: "mae=M max=X" between two AO images of one size (0..1), or
 * "size differs".
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

static int cmp_f(const void *a, const void *b)
{
	const float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

static unsigned px16(const struct dao_frame *f, int x, int y)
{
	uint16_t v;
	memcpy(&v, (const unsigned char *)f->data + (size_t)y * f->stride + 2 * (size_t)x, 2);
	return v;
}

/* the occlusion estimate at (x, y), z in metres (0 = none) */
static double proxy(const float *z, int w, int h, int x, int y, double focal)
{
	static const int dir[8][2] = { { 1, 0 }, { 1, 1 }, { 0, 1 }, { -1, 1 },
				       { -1, 0 }, { -1, -1 }, { 0, -1 }, { 1, -1 } };
	static const int dist[4] = { 3, 6, 12, 24 };
	const double zc = z[(size_t)y * w + x];
	double sum = 0;
	int n = 0;
	for (int d = 0; d < 8; d++)
		for (int k = 0; k < 4; k++) {
			const int xs = x + dir[d][0] * dist[k], ys = y + dir[d][1] * dist[k];
			if (xs < 0 || ys < 0 || xs >= w || ys >= h)
				continue;
			const double zs = z[(size_t)ys * w + xs];
			if (zs <= 0)
				continue;
			const double lateral = dist[k] * hypot(dir[d][0], dir[d][1]) * zc / focal;
			const double t = (zc - zs) / lateral;
			sum += t < 0 ? 0 : t > 2 ? 2 : t;
			n++;
		}
	return n ? sum / n : 0;
}

static int diff(const char *a_path, const char *b_path)
{
	struct dao_frame a, b;
	struct dao_error err;
	if (dao_png_read(a_path, &a, &err) || dao_png_read(b_path, &b, &err)) {
		fprintf(stderr, "ao_stats: %s\n", err.message);
		return 1;
	}
	if (a.format != DAO_PIXFMT_GRAY16 || b.format != DAO_PIXFMT_GRAY16 || a.width != b.width ||
	    a.height != b.height) {
		printf("size differs\n");
	} else {
		double sum = 0, mx = 0;
		for (int y = 0; y < (int)a.height; y++)
			for (int x = 0; x < (int)a.width; x++) {
				const double d = fabs((double)px16(&a, x, y) - px16(&b, x, y)) / 65535.0;
				sum += d;
				mx = d > mx ? d : mx;
			}
		printf("mae=%.3e max=%.4f\n", sum / ((double)a.width * a.height), mx);
	}
	dao_frame_free(&a);
	dao_frame_free(&b);
	return 0;
}

int main(int argc, char **argv)
{
	if (argc == 4 && !strcmp(argv[1], "--diff"))
		return diff(argv[2], argv[3]);
	if (argc != 5 && argc != 6) {
		fprintf(stderr, "usage: ao_stats AO.png DEPTH.png UNIT FOCAL [MASK.png]\n"
				"       ao_stats --diff AO.png REF.png\n");
		return 2;
	}
	const float unit = strtof(argv[3], NULL);
	const double focal = strtod(argv[4], NULL);
	struct dao_frame ao, depth, mask = { 0 };
	struct dao_error err;
	if (dao_png_read(argv[1], &ao, &err) || dao_png_read_depth(argv[2], unit, &depth, &err) ||
	    (argc == 6 && dao_png_read(argv[5], &mask, &err))) {
		fprintf(stderr, "ao_stats: %s\n", err.message);
		return 1;
	}
	if (ao.format != DAO_PIXFMT_GRAY16 || depth.format != DAO_PIXFMT_DEPTH16 ||
	    (argc == 6 && mask.format != DAO_PIXFMT_GRAY8)) {
		fprintf(stderr, "ao_stats: expected a gray16 AO, a 16-bit depth and a gray8 mask\n");
		return 1;
	}
	const int w = (int)depth.width, h = (int)depth.height;
	int holes_ok = ao.width == depth.width && ao.height == depth.height &&
		       (argc == 5 || (mask.width == depth.width && mask.height == depth.height));
	if (!holes_ok) {
		printf("holes_ok=0\n");
		return 0;
	}
	const size_t np = (size_t)w * h;
	float *z = malloc(np * sizeof(float)), *v = malloc(np * sizeof(float));
	if (!z || !v)
		return 1;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++)
			z[(size_t)y * w + x] = (float)px16(&depth, x, y) * unit;
	long n = 0, lit = 0, open = 0, open_dark = 0;
	double sum = 0, open_sum = 0, sp = 0, sq = 0, spp = 0, sqq = 0, spq = 0;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const unsigned a = px16(&ao, x, y);
			if (z[(size_t)y * w + x] <= 0) {
				holes_ok &= a == 65535;
				continue;
			}
			const double vis = a / 65535.0;
			v[n++] = (float)vis;
			sum += vis;
			lit += a == 65535;
			const double p = proxy(z, w, h, x, y, focal), q = 1 - vis;
			sp += p, sq += q, spp += p * p, sqq += q * q, spq += p * q;
			if (argc == 6 &&
			    ((const unsigned char *)mask.data)[(size_t)y * mask.stride + (size_t)x] == 255) {
				open++;
				open_sum += vis;
				open_dark += vis < 0.9;
			}
		}
	double corr = 0;
	if (n > 1) {
		const double cov = spq / n - (sp / n) * (sq / n);
		const double vp = spp / n - (sp / n) * (sp / n), vq = sqq / n - (sq / n) * (sq / n);
		corr = vp > 0 && vq > 0 ? cov / sqrt(vp * vq) : 0;
	}
	qsort(v, (size_t)n, sizeof *v, cmp_f);
#define PCT(q) (n ? (double)v[(size_t)((q) * (double)(n - 1))] : 0.0)
	printf("valid=%ld holes_ok=%d mean=%.4f p05=%.4f p50=%.4f p95=%.4f lit=%.4f corr=%.4f", n,
	       holes_ok, n ? sum / n : 0, PCT(0.05), PCT(0.5), PCT(0.95), n ? (double)lit / n : 0,
	       corr);
	if (argc == 6)
		printf(" open=%ld open_mean=%.4f open_dark=%.4f", open, open ? open_sum / open : 0,
		       open ? (double)open_dark / open : 0);
	printf("\n");
	free(z);
	free(v);
	dao_frame_free(&ao);
	dao_frame_free(&depth);
	if (argc == 6)
		dao_frame_free(&mask);
	return 0;
}
