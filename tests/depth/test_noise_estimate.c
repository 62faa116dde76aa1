/* SPDX-License-Identifier: MIT */
/*
 * The noise estimate of src/depth/noise_estimate.c against noise of known
 * statistics: independent Gaussian noise on tilted planes is recovered (by
 * all three statistics),
 * depth edges and holes do not move it, two halves of different noise are
 * told apart, spatially correlated noise reads as documented, a clean render
 * reads its depth quantum, the cells come out the same computed by rows in
 * any order, and prefilter=domain interpolates the cells bilinearly.  With
 * noise-interval (noise_reuse.h): a cell measured again on its own equals
 * the whole frame's measurement of it, and the check finds the cells the
 * scene moved in and calls a cut when most moved.  The fast block statistics
 * and cell medians equal their scalar oracles bit for bit.  Depth in
 * quantised bands reads the step in every cell.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/cpu.h>

#include "common/cmocka_all.h"
#include "common/noise_fields.h"
#include "common/test_common.h"
#include "depth/domain.h"
#include "depth/noise_estimate.h"
#include "depth/noise_reuse.h"
#include "pipeline/kernels.h"
#include "synth/synth.h"

enum { W = 640, H = 480 };

/* 1/z of a tilted plane at pixel (x, y): 1.3 m to 3.6 m over the frame */
static double plane_w(int x, int y)
{
	return 0.5 + 0.0006 * (x - 320) + 0.0004 * (y - 240);
}

/* z from the plane plus noise in 1/z (n: W x H, NULL for none) */
static void plane_depth(float *z, const float *n)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			z[y * W + x] = (float)(1.0 / (plane_w(x, y) + (n ? n[y * W + x] : 0.0f)));
}

static struct dao_noise_grid estimate(const float *z)
{
	struct dao_noise_grid g;
	assert_int_equal(dao_noise_grid_init(&g, W, H), 0);
	dao_noise_blocks(&g, z, 0, g.bh);
	dao_noise_cells(&g);
	return g;
}

/* RMS over the cells of (cell / sigma - 1) */
static double cell_spread(const struct dao_noise_grid *g, const float *cells, double sigma)
{
	double s = 0;
	for (int i = 0; i < g->cw * g->ch; i++)
		s += (cells[i] / sigma - 1) * (cells[i] / sigma - 1);
	return sqrt(s / (g->cw * g->ch));
}

/* Independent Gaussian noise: all three statistics read sigma. */
static void test_iid(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *n = malloc(W * H * sizeof(float));
	static const double sigmas[] = { 0.0002, 0.0012, 0.005 };
	for (int k = 0; k < 3; k++) {
		dao_test_correlated_noise(n, W, H, sigmas[k], 0.0, 100 + k);
		plane_depth(z, n);
		struct dao_noise_grid g = estimate(z);
		const int nc = g.cw * g.ch;
		const double ea = g.frame_area / sigmas[k], el = g.frame_link / sigmas[k];
		const double es = g.frame_slope / sigmas[k];
		const double sa = cell_spread(&g, g.cell, sigmas[k]);
		const double sl = cell_spread(&g, g.cell + nc, sigmas[k]);
		const double ss = cell_spread(&g, g.cell + 3 * nc, sigmas[k]);
		print_message("iid sigma %.4f: area %.3f sigma (cells %.3f RMS), link %.3f sigma (cells %.3f), "
			      "slope %.3f sigma (cells %.3f)\n", sigmas[k], ea, sa, el, sl, es, ss);
		assert_int_equal(g.usable_cells, nc);
		/* measured: within 1 %, slope 2.3 %; cells 3 %, 9 % and 19 % */
		assert_true(fabs(ea - 1) < 0.03 && fabs(el - 1) < 0.03 && fabs(es - 1) < 0.05);
		assert_true(sa < 0.06 && sl < 0.15 && ss < 0.25);
		dao_noise_grid_free(&g);
	}
	free(z);
	free(n);
}

/* Depth edges and holes: blocks on them are outvoted within their cell. */
static void test_edges_and_holes(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *n = malloc(W * H * sizeof(float));
	const double sigma = 0.0012;
	dao_test_correlated_noise(n, W, H, sigma, 0.0, 7);
	plane_depth(z, n);
	/* a box 0.8 m in front, steps every 40 px, holes in clumps */
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			float *p = &z[y * W + x];
			if (x > 200 && x < 440 && y > 100 && y < 380)
				*p -= 0.8f;
			if ((x / 40) & 1)
				*p += 0.05f;
			if ((x * 31 + y * 17) % 97 == 0)
				*p = 0.0f;
		}
	struct dao_noise_grid g = estimate(z);
	print_message("edges and holes: area %.3f sigma, link %.3f sigma, slope %.3f sigma, "
		      "%d of %d cells usable\n", g.frame_area / sigma, g.frame_link / sigma,
		      g.frame_slope / sigma, g.usable_cells, g.cw * g.ch);
	assert_true(fabs(g.frame_area / sigma - 1) < 0.1 && fabs(g.frame_link / sigma - 1) < 0.1);
	/* a pair of planes across a step differs by the step: with one every
	 * 40 px (a fifth of the pairs across x) slope reads 1.22 sigma */
	assert_true(g.frame_slope / sigma > 0.95 && g.frame_slope / sigma < 1.35);
	dao_noise_grid_free(&g);
	/* with a corner of 3 x 3 cells without data: the cells one row at a
	 * time, in reverse order (as threads may run them), then the frame give
	 * the same grid (usable and filled cells) as dao_noise_cells */
	for (int y = 0; y < 96; y++)
		for (int x = 0; x < 96; x++)
			z[y * W + x] = 0.0f;
	g = estimate(z);
	struct dao_noise_grid g2;
	assert_int_equal(dao_noise_grid_init(&g2, W, H), 0);
	dao_noise_blocks(&g2, z, 0, g2.bh);
	for (int cy = g2.ch - 1; cy >= 0; cy--)
		dao_noise_cell_rows(&g2, cy, cy + 1);
	dao_noise_cells_finish(&g2);
	assert_int_equal(g.usable_cells, g.cw * g.ch - 9);
	assert_int_equal(g2.usable_cells, g.usable_cells);
	assert_memory_equal(g2.cell, g.cell, DAO_NOISE_CELL_STATS * (size_t)g.cw * g.ch * sizeof(float));
	assert_true(g2.frame_area == g.frame_area && g2.frame_link == g.frame_link &&
		    g2.frame_w == g.frame_w && g2.frame_slope == g.frame_slope);
	dao_noise_grid_free(&g2);
	dao_noise_grid_free(&g);
	/* everything a hole: nothing measured */
	memset(z, 0, W * H * sizeof(float));
	g = estimate(z);
	assert_int_equal(g.usable_cells, 0);
	assert_true(isnan(g.frame_area));
	dao_noise_grid_free(&g);
	free(z);
	free(n);
}

/* Two halves: the cells follow the noise of their half. */
static void test_regions(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *n = malloc(W * H * sizeof(float));
	dao_test_correlated_noise(n, W, H, 1.0, 0.0, 9);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			n[y * W + x] *= x < W / 2 ? 0.0005f : 0.003f;
	plane_depth(z, n);
	struct dao_noise_grid g = estimate(z);
	for (int cy = 0; cy < g.ch; cy++)
		for (int cx = 0; cx < g.cw; cx++) {
			const double want = cx < g.cw / 2 ? 0.0005 : 0.003;
			const float a = g.cell[cy * g.cw + cx];
			if (fabs(a / want - 1) > 0.15)
				fail_msg("cell %d,%d: area %g, the noise there is %g", cx, cy, (double)a, want);
		}
	dao_noise_grid_free(&g);
	free(z);
	free(n);
}

/*
 * Spatially correlated noise (white noise blurred by blur px, standard
 * deviation sigma): `area` reads the part an 8x8 plane cannot absorb,
 * `link` what neighbours differ by, `slope` how much blobs tilt the 8x8
 * planes (more than independent noise of the same sigma would, up to blobs
 * of about a block).  Bounds: measured values with margin.
 */
static void test_correlated(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *n = malloc(W * H * sizeof(float));
	const double sigma = 0.0012;
	static const struct {
		double blur, area_lo, area_hi, link_lo, link_hi, slope_lo, slope_hi;
	} cases[] = {
		{ 0.5, 0.90, 1.00, 0.68, 0.90, 1.30, 1.56 },   /* measured 0.965, 0.785, 1.433 */
		{ 1.0, 0.72, 0.88, 0.15, 0.23, 2.35, 2.85 },   /* 0.799, 0.189, 2.596 */
		{ 2.0, 0.43, 0.55, 0.020, 0.040, 3.05, 3.70 }, /* 0.487, 0.029, 3.366 */
		{ 4.0, 0.15, 0.22, 0.002, 0.007, 2.15, 2.62 }, /* 0.181, 0.004, 2.377 */
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		dao_test_correlated_noise(n, W, H, sigma, cases[k].blur, 20 + k);
		plane_depth(z, n);
		struct dao_noise_grid g = estimate(z);
		const double a = g.frame_area / sigma, l = g.frame_link / sigma;
		const double sl = g.frame_slope / sigma;
		print_message("correlated, blur %.1f px: area %.3f sigma, link %.3f sigma, slope %.3f sigma\n",
			      cases[k].blur, a, l, sl);
		assert_true(a > cases[k].area_lo && a < cases[k].area_hi);
		assert_true(l > cases[k].link_lo && l < cases[k].link_hi);
		assert_true(sl > cases[k].slope_lo && sl < cases[k].slope_hi);
		dao_noise_grid_free(&g);
	}
	free(z);
	free(n);
}

/* A clean render in millimetres: the estimate is the depth quantum only. */
static void test_clean_render(void **state)
{
	(void)state;
	static const char *const scenes[] = { "plane", "room-corner", "spheres", "boxes" };
	for (int k = 0; k < 4; k++) {
		struct synth_scene sc;
		struct synth_image img;
		struct dao_camera cam;
		assert_int_equal(synth_scene_build(scenes[k], 0.0, &sc, NULL), 0);
		synth_default_camera(&cam);
		assert_int_equal(synth_render(&sc, &cam, 0.5, 0, 2, &img, NULL), 0);
		double q = 0;
		int nq = 0;
		for (int i = 0; i < W * H; i++) {
			img.depth[i] = roundf(img.depth[i] * 1000.0f) / 1000.0f;
			if (img.depth[i] > 0)
				q += 0.001 / (img.depth[i] * img.depth[i]) / sqrt(12.0), nq++;
		}
		q /= nq; /* the quantum's standard deviation in 1/z, on average */
		struct dao_noise_grid g = estimate(img.depth);
		print_message("clean %-12s area %.2e link %.2e slope %.2e, quantum sigma %.2e (1/z)\n",
			      scenes[k], (double)g.frame_area, (double)g.frame_link,
			      (double)g.frame_slope, q);
		assert_true(g.frame_area > 0.5 * q && g.frame_area < 1.5 * q);
		assert_true(g.frame_link > 0.5 * q && g.frame_link < 1.5 * q);
		/* the quantum tilts no plane much: often exactly 0 */
		assert_true(g.frame_slope < 1.5 * q);
		dao_noise_grid_free(&g);
		synth_image_free(&img);
	}
}

/*
 * Depth in quantised bands (a Kinect far away: one disparity step is 50 mm
 * at 4 m), every band 16 px wide, so that half of the blocks lie inside one
 * band and have no non-zero link: the cells' link is still the step's, not
 * a value between 0 and it that moved with the share of blocks a band edge
 * crosses (the Kinect recording's frame 4 read 0.45 of its neighbours in one
 * cell, and the three frames that reused it filtered bands into stairs).
 */
static void test_quantised_bands(void **state)
{
	(void)state;
	const double q = 0.003; /* the band step in 1/z, 1/m */
	float *z = malloc(sizeof(float) * W * H);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) /* steps between x = 16 k + 11 and 16 k + 12 */
			z[y * W + x] = (float)(1.0 / (0.25 + q * floor((x + 4) / 16.0)));
	struct dao_noise_grid g = estimate(z);
	/* inside a block with a step, one difference per row is the step */
	const double step = q / DAO_NOISE_LINK_IID;
	const int nc = g.cw * g.ch;
	print_message("bands: frame link %.3e, step %.3e\n", (double)g.frame_link, step);
	assert_int_equal(g.usable_cells, nc);
	for (int i = 0; i < nc; i++)
		assert_true(fabs(g.cell[nc + i] / step - 1) < 0.01);
	assert_true(fabs(g.frame_link / step - 1) < 0.01);
	/* a cell measured alone (noise-interval's cells) reads the same */
	float link = 0.0f, w = 0.0f;
	assert_int_equal(dao_noise_cell_measure(&g, z, 3, 2, &link, &w), 1);
	assert_true(link == g.cell[nc + 2 * g.cw + 3]);
	dao_noise_grid_free(&g);
	free(z);
}

/* The maps: the cell's value at its centre, linear between centres,
 * constant beyond, and the transposed map the same numbers. */
/* The value of a cell grid where prefilter=domain's passes read it
 * (dao_domain_cell_knots then dao_domain_cell_pos, domain.h), in both
 * directions of pass: bilinear between the cell centres. */
static float domain_cell_value(const struct dao_noise_grid *g, const float *cells, int vertical,
			       int x, int y)
{
	const struct dao_domain_setup s = {
		.width = W, .height = H, .iterations = 1, .inv_scale = 1.0f, .noise = 1.0f,
		.noise_cells = cells, .cells_x = g->cw, .cells_y = g->ch,
		.cell_span = DAO_NOISE_BLOCK * DAO_NOISE_CELL,
	};
	struct dao_domain_pass p;
	dao_domain_pass_init(&p, &s, vertical ? 0 : 1, NULL, NULL);
	float knots[64];
	assert_true(p.line_cells <= 64);
	dao_domain_cell_knots(&p, cells, vertical ? x : y, knots, 1);
	int k;
	float u;
	dao_domain_cell_pos(vertical ? y : x, p.line_cells, p.cell_span, &k, &u);
	const float a = knots[k], b = knots[k + 1 < p.line_cells ? k + 1 : k];
	return a + (b - a) * u;
}

static void test_cell_interpolation(void **state)
{
	(void)state;
	struct dao_noise_grid g;
	assert_int_equal(dao_noise_grid_init(&g, W, H), 0);
	const int nc = g.cw * g.ch;
	float *cells = malloc(nc * sizeof(float));
	for (int cy = 0; cy < g.ch; cy++)
		for (int cx = 0; cx < g.cw; cx++)
			cells[cy * g.cw + cx] = (float)(cx * 10 + cy * 1000 + (cx * cy) % 7);
	const int span = DAO_NOISE_BLOCK * DAO_NOISE_CELL; /* cell centres at span k + 15.5 */
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			/* bilinear by hand, in double */
			double fx = (x - 15.5) / span, fy = (y - 15.5) / span;
			fx = fx < 0 ? 0 : fx > g.cw - 1 ? g.cw - 1 : fx;
			fy = fy < 0 ? 0 : fy > g.ch - 1 ? g.ch - 1 : fy;
			int ix = (int)fx, iy = (int)fy;
			ix = ix > g.cw - 2 ? g.cw - 2 : ix;
			iy = iy > g.ch - 2 ? g.ch - 2 : iy;
			const double ux = fx - ix, uy = fy - iy;
			const double c00 = cells[iy * g.cw + ix], c01 = cells[iy * g.cw + ix + 1];
			const double c10 = cells[(iy + 1) * g.cw + ix], c11 = cells[(iy + 1) * g.cw + ix + 1];
			const double want = (1 - uy) * ((1 - ux) * c00 + ux * c01) +
					    uy * ((1 - ux) * c10 + ux * c11);
			const float a = domain_cell_value(&g, cells, 1, x, y);
			const float b = domain_cell_value(&g, cells, 0, x, y);
			if (fabs(a - want) > 1e-3 || fabs(b - want) > 1e-3)
				fail_msg("cells at %d,%d: vertical pass %g, horizontal %g, bilinear %g", x,
					 y, (double)a, (double)b, want);
		}
	free(cells);
	dao_noise_grid_free(&g);
}


/*
 * noise_reuse.h: frame b is frame a with a box nearer (and ToF-like: its
 * noise in 1/z grows as w^2) over the cells [4, 8) x [3, 6), partly
 * covering them.  The check after a's measurement flags those cells and no
 * other; each, measured again on its own, reads what the whole frame's
 * measurement of b reads there, bit for bit.  All of the frame nearer is a
 * cut.
 */
static void test_cells_again(void **state)
{
	(void)state;
	float *za = malloc(W * H * sizeof(float)), *zb = malloc(W * H * sizeof(float));
	float *n = malloc(W * H * sizeof(float));
	dao_test_correlated_noise(n, W, H, 0.001, 0.0, 21);
	plane_depth(za, n);
	dao_test_correlated_noise(n, W, H, 0.001, 0.0, 22);
	plane_depth(zb, n);
	const int span = DAO_NOISE_BLOCK * DAO_NOISE_CELL;
	for (int y = 3 * span + 5; y < 6 * span - 3; y++)
		for (int x = 4 * span + 7; x < 8 * span - 2; x++) {
			const double w = 1.0 / 0.8; /* 0.8 m: 2.25 x the plane's 1/z or more */
			zb[y * W + x] = (float)(1.0 / (w + 0.001 * w * w / 0.25 * n[y * W + x] / 0.001));
		}
	struct dao_noise_grid g = estimate(za), gb = estimate(zb);
	struct dao_noise_reuse r;
	assert_int_equal(dao_noise_reuse_init(&r, &g), 0);
	dao_noise_reuse_restart(&r);
	dao_noise_reuse_store(&r, &g, za, 15);
	assert_true(r.valid);
	assert_int_equal(dao_noise_reuse_changes(&r, &g, za), 0);
	const int moved = dao_noise_reuse_changes(&r, &g, zb);
	assert_int_equal(moved, 4 * 3);
	const int nc = g.cw * g.ch;
	for (int i = 0; i < moved; i++) {
		const int c = r.changed[i], cx = c % g.cw, cy = c / g.cw;
		assert_true(cx >= 4 && cx < 8 && cy >= 3 && cy < 6);
		dao_noise_reuse_measure_cell(&r, &g, zb, i);
		/* the full measurement's cells before filling: those with enough blocks */
		assert_false(isnan(gb.cell[c]));
		assert_true(r.cell[c] == gb.cell[nc + c] && r.cell[nc + c] == gb.cell[2 * nc + c]);
		assert_true(r.cell[c] > 3.0f * g.cell[nc + c]); /* ToF: nearer, noisier in 1/z */
	}
	/* measured again: the reference follows, nothing moved any more */
	assert_int_equal(dao_noise_reuse_changes(&r, &g, zb), 0);
	/* everything 20 % nearer: a cut */
	for (int i = 0; i < W * H; i++)
		zb[i] = za[i] * 0.8f;
	assert_int_equal(dao_noise_reuse_changes(&r, &g, zb), -1);
	dao_noise_reuse_free(&r);
	dao_noise_grid_free(&g);
	dao_noise_grid_free(&gb);
	free(za);
	free(zb);
	free(n);
}

/* 1 where a and b hold the same values (NaN where either is NaN) */
static int same_floats(const float *a, const float *b, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (!(a[i] == b[i] || (isnan(a[i]) && isnan(b[i]))))
			return 0;
	return 1;
}

/* depth of kind k at w x h: noisy planes with steps and holes, millimetre
 * quanta (ties), and random values with zeros, negatives, NaN, +inf and
 * denormals (what float input could hold) */
static void oracle_field(float *z, int w, int h, int k, uint64_t seed)
{
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const double g = dao_test_gauss(&seed);
			const double u = 0.5 + 0.5 * dao_test_gauss(&seed) / 4.0;
			float v = (float)(1.0 / (0.5 + 0.0006 * x + 0.0004 * y + 0.001 * g));
			if ((x / 40) & 1)
				v += 0.05f;
			if (k == 1)
				v = roundf(v * 1000.0f) / 1000.0f;
			if (k == 3) /* bands 50 mm apart at 4 m: blocks inside one */
				v = 1.0f / (0.003f * roundf((0.25f + 0.0002f * x + 0.00004f * y +
							     0.0005f * (float)g) / 0.003f));
			if (k == 2) {
				v = (float)(0.2 + 8.0 * u * u);
				const uint64_t r = seed % 200;
				v = r == 0 ? 0.0f : r == 1 ? -v : r == 2 ? NAN : r == 3 ? INFINITY
				    : r == 4 ? 1e-40f : r == 5 ? 1e-30f : v;
			}
			if ((x * 31 + y * 17) % 211 == 0)
				v = 0.0f;
			z[y * w + x] = v;
		}
}

/*
 * The fast paths against their oracles: dao_noise_cell_rows (sorting
 * networks across cells) against dao_noise_cell_rows_ref (rank medians),
 * the same block statistics in, at sizes with partial cells and blocks
 * (widths not a multiple of 8 cells); the same values bit for bit.
 */
static void test_oracle(void **state)
{
	(void)state;
	static const int sizes[][2] = { { 640, 480 }, { 37, 45 }, { 8, 8 }, { 264, 136 },
					{ 848, 480 }, { 100, 260 }, { 16, 300 } };
	for (size_t si = 0; si < sizeof(sizes) / sizeof(sizes[0]); si++)
		for (int k = 0; k < 4; k++) {
			const int w = sizes[si][0], h = sizes[si][1];
			float *z = malloc((size_t)w * h * sizeof(float));
			oracle_field(z, w, h, k, 1000 + si * 3 + k);
			struct dao_noise_grid a, b;
			assert_int_equal(dao_noise_grid_init(&a, w, h), 0);
			assert_int_equal(dao_noise_grid_init(&b, w, h), 0);
			const size_t nb = DAO_NOISE_BLOCK_STATS * (size_t)a.bw * a.bh;
			const size_t nc = DAO_NOISE_CELL_STATS * (size_t)a.cw * a.ch;
			dao_noise_blocks_ref(&a, z, 0, a.bh);
			/* every kernel set this CPU runs, the reference set last */
			for (int s = DAO_SIMD_GENERIC; s <= DAO_SIMD_COUNT; s++) {
				const enum dao_simd set = s < DAO_SIMD_COUNT ? (enum dao_simd)s
									     : DAO_SIMD_REFERENCE;
				if (s < DAO_SIMD_COUNT && !dao_simd_supported(set))
					continue;
				struct dao_kernels kr;
				dao_kernels_select(&kr, set);
				b.row = kr.noise_row;
				memset(b.block, 0, nb * sizeof(float));
				dao_noise_blocks(&b, z, 0, b.bh);
				if (!same_floats(a.block, b.block, nb))
					fail_msg("%dx%d field %d: set %d's block statistics differ", w, h,
						 k, s);
			}
			dao_noise_cell_rows_ref(&a, 0, a.ch);
			dao_noise_cell_rows(&b, 0, b.ch);
			assert_true(same_floats(a.cell, b.cell, nc));
			dao_noise_cells_finish(&a);
			dao_noise_cells_finish(&b);
			assert_int_equal(a.usable_cells, b.usable_cells);
			assert_true(same_floats(a.cell, b.cell, nc));
			if (k != 2 && w >= 64 && h >= 64)
				assert_true(a.usable_cells > 0);
			dao_noise_grid_free(&a);
			dao_noise_grid_free(&b);
			free(z);
		}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_iid),
		cmocka_unit_test(test_edges_and_holes),
		cmocka_unit_test(test_regions),
		cmocka_unit_test(test_correlated),
		cmocka_unit_test(test_clean_render),
		cmocka_unit_test(test_quantised_bands),
		cmocka_unit_test(test_cell_interpolation),
		cmocka_unit_test(test_cells_again),
		cmocka_unit_test(test_oracle),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
