/* SPDX-License-Identifier: MIT */
/*
 * AO over colour: the colour image of an RGB-D sensor darkened by the
 * ambient occlusion of its depth ("overlay"), what depthaod's overlay
 * stream, depthao process --overlay-out, the GStreamer element and
 * Python's AO.overlay() show.
 *
 * Each channel: out = round(c x a / 65535), a = the visibility as 16 bits
 * (GRAY16 as it is, GRAY8 x 257, GRAY_F32 round(v x 65535) after clamping
 * to [0, 1]).  Open surfaces (visibility 1) keep their colour exactly.
 *
 * Registration: the overlay has the AO's (the depth's) size.  Colour of the
 * same size is used pixel for pixel; colour of another size with the same
 * aspect ratio (within 1 %, e.g. 1280x960 over 640x480 depth) is resampled
 * to it bilinearly (pixel centres aligned); other aspect ratios are refused
 * (-EINVAL): the two images do not show the same view, and depthao does not
 * reproject between cameras.  Whether depth is registered to the colour
 * camera is the source's business (dao_source_info.registered); unregistered
 * depth makes an overlay offset by the parallax between the two cameras.
 */
#ifndef DEPTHAO_OVERLAY_H
#define DEPTHAO_OVERLAY_H

#include <stdint.h>

#include <depthao/error.h>
#include <depthao/frame.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * 0 if colour of color_w x color_h can be laid over AO of ao_w x ao_h (same
 * size or same aspect ratio), else -EINVAL with a message giving both sizes.
 */
DAO_API int dao_overlay_check(uint32_t color_w, uint32_t color_h, uint32_t ao_w, uint32_t ao_h,
			      struct dao_error *err);

/*
 * Lays `ao` (GRAY16, GRAY8 or GRAY_F32) over `color` (RGB24) into `out`
 * (RGB24, the AO's size), all caller-owned with any stride.  No allocation.
 */
DAO_API int dao_overlay(const struct dao_frame *color, const struct dao_frame *ao,
			struct dao_frame *out, struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
