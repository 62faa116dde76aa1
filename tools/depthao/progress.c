/* SPDX-License-Identifier: MIT */
#include <stdio.h>
#include <unistd.h>

#include "progress.h"

#define BAR_WIDTH 30

void progress_begin(struct progress *p, size_t total, int quiet)
{
	p->total = total;
	p->enabled = !quiet && total > 1 && isatty(STDERR_FILENO);
}

void progress_update(struct progress *p, size_t done, double ms_per_frame)
{
	if (!p->enabled)
		return;
	int fill = (int)(BAR_WIDTH * done / p->total);
	char bar[BAR_WIDTH + 1];
	for (int i = 0; i < BAR_WIDTH; i++)
		bar[i] = i < fill ? '#' : '.';
	bar[BAR_WIDTH] = '\0';
	fprintf(stderr, "\r[%s] %zu/%zu  %.1f ms/frame", bar, done, p->total, ms_per_frame);
	fflush(stderr);
}

void progress_end(struct progress *p)
{
	if (p->enabled)
		fputs("\r\033[K", stderr); /* clear the bar's line */
}
