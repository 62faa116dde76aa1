/* SPDX-License-Identifier: MIT */
#ifndef DAO_TOOLS_PROGRESS_H
#define DAO_TOOLS_PROGRESS_H

#include <stddef.h>

/* A one-line progress bar on stderr, drawn only when stderr is a terminal. */
struct progress {
	size_t total;
	int enabled;
};

void progress_begin(struct progress *p, size_t total, int quiet);
void progress_update(struct progress *p, size_t done, double ms_per_frame);
void progress_end(struct progress *p);

#endif
