/* SPDX-License-Identifier: MIT */
/*
 * The C face of the libcamera shim (lc_shim.cpp; libcamera is C++ only).
 * A camera streams a mono raw format (R12, R10 or R8 in 0.0.3; 16-bit
 * little-endian containers for R10/R12) that ToF sensors use for depth.
 */
#ifndef DAO_LC_SHIM_H
#define DAO_LC_SHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct lcs_camera;

/* Calls cb(user, id, model) per camera; returns the count or < 0 (msg in err). */
int lcs_list(void (*cb)(void *user, const char *id, const char *model), void *user, char *err,
	     size_t cap);

/* Opens camera `id` ("any" = the first) at about w x h (0 = its default). */
struct lcs_camera *lcs_open(const char *id, unsigned w, unsigned h, char *err, size_t cap);
void lcs_describe(const struct lcs_camera *c, unsigned *w, unsigned *h, unsigned *bits,
		  char *text, size_t cap);
int lcs_start(struct lcs_camera *c, char *err, size_t cap);
/*
 * The next frame as 16-bit samples (valid until the next call): 0, -EAGAIN
 * after timeout_ms, -ENODEV when the camera went away.
 */
int lcs_read(struct lcs_camera *c, int timeout_ms, const uint16_t **data, unsigned *stride_bytes,
	     uint64_t *timestamp_ns, uint64_t *sequence);
void lcs_close(struct lcs_camera *c);

#ifdef __cplusplus
}
#endif
#endif
