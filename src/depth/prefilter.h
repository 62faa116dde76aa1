/* SPDX-License-Identifier: MIT */
#ifndef DAO_DEPTH_PREFILTER_H
#define DAO_DEPTH_PREFILTER_H

/*
 * Edge-preserving depth prefilter (bilateral in inverse depth).
 *
 * Structured-light noise is roughly constant in disparity, i.e. in 1/z:
 * sigma(z) = k z^2 m  <=>  sigma(1/z) = k.  Filtering w = 1/z therefore has
 * one noise level for the whole frame, and since 1/z is an affine function
 * of the pixel on any plane, a symmetric kernel leaves planes exactly in
 * place.  Range weights use the difference in w against
 * sigma_w(z) = max(k, unit / z^2) (the larger of sensor noise and depth
 * quantisation), so depth edges are kept.
 *
 * z, out: w x h planes of metres, 0 = no data (stays 0: holes are not filled).
 * Processes rows [y0, y1); out must not alias z.
 */
void dao_prefilter_bilateral(const float *z, float *out, int w, int h, int radius,
			     float noise_k, float unit, int y0, int y1);

#endif
