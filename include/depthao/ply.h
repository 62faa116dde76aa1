/* SPDX-License-Identifier: MIT */
/* Part of libdepthao-io (pkg-config depthao-io, <depthao/io.h>), not of the AO core libdepthao. */
/*
 * Point clouds as PLY files (binary, little-endian), readable by Open3D,
 * CloudCompare, MeshLab and PCL.
 */
#ifndef DEPTHAO_PLY_H
#define DEPTHAO_PLY_H

#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>
#include <depthao/frame.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Writes the pixels of `depth` that have depth as a point cloud to `path`:
 * one vertex per such pixel, in row order, at its back-projection through
 * `cam` (optical frame: x right, y down, z forward, metres; x = (u - cx) / fx * z,
 * y = (v - cy) / fy * z).
 *
 * depth: DEPTH16 (counts of depth_unit metres, 0 = no data) or DEPTH_F32
 * (metres; 0, negative, NaN and inf = no data), of the camera's size.
 * ao: NULL, or the AO of the same frame as GRAY_F32 (visibility, 1 = open),
 * GRAY16 (round(v x 65535)) or GRAY8 (round(v x 255)), of the same size.
 *
 * Vertex properties: float x, y, z; with `ao` also uchar red, green, blue
 * (the grey round(v x 255)) and float scalar_ao (v in [0, 1]; CloudCompare
 * reads "scalar_" properties as scalar fields).  The file is written
 * atomically like dao_png_write() (a temporary file renamed into place;
 * FIFOs and character devices written straight into).  `points` (may be
 * NULL) receives the vertex count.  Returns 0 or a negative errno.
 */
DAO_API int dao_ply_write(const char *path, const struct dao_camera *cam,
			  const struct dao_frame *depth, const struct dao_frame *ao,
			  uint64_t *points, struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
