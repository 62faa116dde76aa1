/* SPDX-License-Identifier: MIT */
/*
 * The working memory of the tile kernels (gtao_tile.inc.c: GTAO and VBAO
 * with tile noise): per tile phase the tables of sample taps, and the steps
 * of one slice when a table cannot hold every slice.  About 70 KB, so it is
 * not on the stack: the context allocates one per pool thread when it starts
 * its threads and hands each band its thread's (dao_pool_run_threads), and a
 * worker thread needs no more stack than the C library gives it.
 */
#ifndef DAO_KERNELS_GTAO_TILE_H
#define DAO_KERNELS_GTAO_TILE_H

#include <stdint.h>

#include <depthao/params.h>

/* One step of a side, the same for every pixel of a block, relative to its row. */
struct tile_step {
	int32_t o0, o1;     /* the taps: entries from the row's first entry of phase 0,
			     * before the block's first entry is added */
	int32_t oe;         /* the tap an edge takes (the one closer to the line) */
	int32_t dr_lo, dr_hi; /* rows of the taps relative to the pixel's */
	int32_t dc_lo, dc_hi; /* columns of the taps relative to the pixel's: a step
			       * whose taps are all off the image for every lane of a
			       * block is skipped (it would sample nothing) */
	float f;            /* fraction between the taps */
	float ux_s, ux_e;   /* (u_sample - u_pixel) ax, smooth (s) and at an edge (e) */
	float vy_s, vy_e;   /* (v_sample - v_pixel) ay, smooth and at an edge */
	float c_s, c_e;     /* ux^2 + vy^2, smooth and at an edge */
	int flags;
};

/*
 * Tables of steps for one tile phase and tile row (y mod 4), one per block
 * radius seen: as many as fit in TILE_STEPS_MAX entries, up to TILE_TABLES,
 * replaced oldest first.
 */
#define TILE_STEPS_MAX 256 /* the steps of every preset fit (ultra: 192) */
#define TILE_TABLES 8
struct tile_cache {
	int per;    /* entries per table: slices x 2 x steps */
	int count;  /* tables that fit */
	int next;   /* the one to replace next */
	float rp[TILE_TABLES]; /* the radius each table was made for (-1: none) */
	int reach_r[TILE_TABLES], reach_c[TILE_TABLES]; /* largest |row|, |column| offset of a tap */
	int steps;  /* entries per slice side (a run of them in a table) */
	/* per table and slice side: the least dr_hi, the largest dr_lo, the least
	 * dc_hi and the largest dc_lo of its steps, so that a block tells once per
	 * side whether tile_skip could skip any of them (tile_side_checks) */
	int32_t side_lim[TILE_TABLES][2 * DAO_MAX_SLICES][4];
	struct tile_step st[TILE_STEPS_MAX];
};

/* One thread's scratch: the four tile phases' tables, one slice's steps. */
struct dao_tile_scratch {
	struct tile_cache cache[4];
	struct tile_step local[2 * DAO_MAX_STEPS];
};

#endif
