/* SPDX-License-Identifier: MIT */
/*
 * V4L2 output, for v4l2loopback virtual cameras: the shaded (RGB24) or AO
 * (GRAY8) stream written with write() in YUYV (what browsers, OBS and video
 * calls take; the default), RGB24 or GREY.  YUYV needs an even width.
 *
 * URI: /dev/videoN[?format=YUYV|RGB24|GREY&fps=N]
 */
#ifndef DAO_V4L2_OUTPUT_H
#define DAO_V4L2_OUTPUT_H

#include <depthao/plugin.h>

#include "v4l2_io.h"

struct v4l2out;

int v4l2out_open(const struct v4l2_io *io, const char *uri, struct v4l2out **out,
		 struct dao_error *err);
int v4l2out_negotiate(struct v4l2out *o, struct dao_sink_format *fmt, struct dao_error *err);
int v4l2out_write(struct v4l2out *o, const struct dao_frame *f, struct dao_error *err);
/* Frames the device could not take (no room: a busy or absent consumer). */
uint64_t v4l2out_dropped(const struct v4l2out *o);
void v4l2out_close(struct v4l2out *o);

/* RGB24 or GRAY8 row(s) to YUYV (BT.601, limited range); width even. */
void v4l2_rgb_to_yuyv(const uint8_t *rgb, uint32_t w, uint8_t *yuyv);
void v4l2_gray_to_yuyv(const uint8_t *gray, uint32_t w, uint8_t *yuyv);

#endif
