/* SPDX-License-Identifier: MIT */
/* Row bands on a few threads, for the sensor simulations (tools and tests only). */
#ifndef DAO_SYNTH_PARALLEL_H
#define DAO_SYNTH_PARALLEL_H

/*
 * Calls fn(ctx, band, y0, y1) for `bands` contiguous bands of rows [0, h),
 * one thread each (the caller's thread takes the first; a band whose thread
 * cannot start runs on the caller's).  bands is clamped to [1, 64]; band
 * limits are multiples of `align` (>= 1).  The result must not depend on the
 * number of bands.
 */
void synth_parallel_rows(int h, int bands, int align,
			 void (*fn)(void *ctx, int band, int y0, int y1), void *ctx);

#endif
