/* SPDX-License-Identifier: MIT */
/*
 * V4L2 depth capture: Z16 (RealSense and other UVC depth cameras), Y16 (16-bit
 * depth in a grey format) with a configurable unit, and Y10B (Kinect v1 raw
 * disparity from gspca_kinect, converted to millimetres).  MMAP streaming
 * with a small ring, poll with a timeout, -ENODEV when the device goes away.
 *
 * URI: DEVICE[?size=WxH&fps=N&format=Z16|Y16|Y10B&unit=M]; DEVICE is a node
 * (/dev/video2), "card=NAME" or "bus=BUS_INFO" (as 'depthao devices' lists
 * them), or "any" (the first node with a depth format).
 */
#ifndef DAO_V4L2_CAPTURE_H
#define DAO_V4L2_CAPTURE_H

#include <depthao/plugin.h>

#include "v4l2_io.h"

struct v4l2cap;

int v4l2cap_open(const struct v4l2_io *io, const char *uri, const struct dao_source_options *opts,
		 struct v4l2cap **out, struct dao_error *err);
void v4l2cap_info(const struct v4l2cap *c, struct dao_source_info *info);
int v4l2cap_start(struct v4l2cap *c, struct dao_error *err);
int v4l2cap_read(struct v4l2cap *c, struct dao_source_frame *f, int timeout_ms,
		 struct dao_error *err);
void v4l2cap_stop(struct v4l2cap *c);
void v4l2cap_close(struct v4l2cap *c);

/* Depth-capable capture nodes: one entry per node with its depth formats and sizes. */
int v4l2cap_list(const struct v4l2_io *io, dao_device_cb cb, void *user, struct dao_error *err);

/* Kinect v1 disparity (11-bit, 2047 = none) to millimetres, 0 when out of range. */
uint16_t v4l2_kinect_disparity_to_mm(unsigned d);

#endif
