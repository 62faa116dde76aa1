/* SPDX-License-Identifier: MIT */
#include <pthread.h>

#include "synth/parallel.h"

struct band {
	void (*fn)(void *ctx, int band, int y0, int y1);
	void *ctx;
	int index, y0, y1;
};

static void *run_band(void *arg)
{
	struct band *b = arg;
	b->fn(b->ctx, b->index, b->y0, b->y1);
	return NULL;
}

/* Row k/bands of the way down, rounded to a multiple of align (h at the end). */
static int limit(int h, int k, int bands, int align)
{
	if (k >= bands)
		return h;
	int y = (int)((long)h * k / bands);
	y -= y % align;
	return y;
}

void synth_parallel_rows(int h, int bands, int align,
			 void (*fn)(void *ctx, int band, int y0, int y1), void *ctx)
{
	if (align < 1)
		align = 1;
	if (bands > 64)
		bands = 64;
	if (bands > (h + align - 1) / align)
		bands = (h + align - 1) / align;
	if (bands < 1)
		bands = 1;
	struct band b[64];
	pthread_t tid[64];
	int ok[64] = { 0 };
	for (int k = 0; k < bands; k++)
		b[k] = (struct band){ fn, ctx, k, limit(h, k, bands, align),
				      limit(h, k + 1, bands, align) };
	for (int k = 1; k < bands; k++)
		ok[k] = pthread_create(&tid[k], NULL, run_band, &b[k]) == 0;
	run_band(&b[0]);
	for (int k = 1; k < bands; k++) {
		if (ok[k])
			pthread_join(tid[k], NULL);
		else
			run_band(&b[k]);
	}
}
