/* SPDX-License-Identifier: MIT */
/*
 * Point clouds as binary little-endian PLY (the format of Turk's PLY
 * description, as rply, Open3D and CloudCompare read it): a header, then
 * the vertices one after the other, each property in the order declared.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "core/error_internal.h"
#include "file/output_file_internal.h"

/* x, y, z float; red, green, blue uchar; scalar_ao float */
#define VERTEX_XYZ 12
#define VERTEX_AO 19
#define VERTICES_PER_WRITE 256

static int checked_inputs(const char *path, const struct dao_camera *cam,
			  const struct dao_frame *depth, const struct dao_frame *ao,
			  struct dao_error *err)
{
	if (!path || !*path)
		return dao_error_set(err, -EINVAL, "PLY write: no output path");
	if (!cam)
		return dao_error_set(err, -EINVAL, "PLY write '%s': no camera", path);
	int r = dao_frame_check(depth, "point cloud depth", cam->width, cam->height, err);
	if (r)
		return r;
	if (depth->format != DAO_PIXFMT_DEPTH16 && depth->format != DAO_PIXFMT_DEPTH_F32)
		return dao_error_set(err, -EINVAL,
				     "point cloud depth for '%s' must be depth16 or depth_f32, not %s",
				     path, dao_pixfmt_name(depth->format));
	if (depth->format == DAO_PIXFMT_DEPTH16 &&
	    !(isfinite(depth->depth_unit) && depth->depth_unit > 0))
		return dao_error_set(err, -EINVAL,
				     "point cloud depth for '%s': depth_unit %g must be > 0 metres "
				     "per count", path, (double)depth->depth_unit);
	if (!ao)
		return 0;
	if ((r = dao_frame_check(ao, "point cloud AO", cam->width, cam->height, err)))
		return r;
	if (ao->format != DAO_PIXFMT_GRAY_F32 && ao->format != DAO_PIXFMT_GRAY16 &&
	    ao->format != DAO_PIXFMT_GRAY8)
		return dao_error_set(err, -EINVAL,
				     "point cloud AO for '%s' must be gray_f32, gray16 or gray8, not %s",
				     path, dao_pixfmt_name(ao->format));
	return 0;
}

/* Depth of pixel x of a row in metres, or 0 where there is none. */
static double depth_at(const struct dao_frame *d, const uint8_t *row, uint32_t x)
{
	if (d->format == DAO_PIXFMT_DEPTH16)
		return ((const uint16_t *)(const void *)row)[x] * (double)d->depth_unit;
	float z = ((const float *)(const void *)row)[x];
	return isfinite(z) && z > 0 ? (double)z : 0.0;
}

/* Visibility of pixel x of a row, in [0, 1]. */
static float visibility_at(const struct dao_frame *a, const uint8_t *row, uint32_t x)
{
	float v;
	switch (a->format) {
	case DAO_PIXFMT_GRAY16:
		return ((const uint16_t *)(const void *)row)[x] / 65535.0f;
	case DAO_PIXFMT_GRAY8:
		return row[x] / 255.0f;
	default:
		v = ((const float *)(const void *)row)[x];
		return v > 0 ? (v < 1 ? v : 1) : 0; /* NaN -> 0 */
	}
}

static uint8_t *put_f32(uint8_t *p, float v)
{
	uint32_t u;
	memcpy(&u, &v, 4);
	p[0] = (uint8_t)u;
	p[1] = (uint8_t)(u >> 8);
	p[2] = (uint8_t)(u >> 16);
	p[3] = (uint8_t)(u >> 24);
	return p + 4;
}

static uint64_t count_points(const struct dao_frame *d)
{
	uint64_t n = 0;
	for (uint32_t y = 0; y < d->height; y++) {
		const uint8_t *row = (const uint8_t *)d->data + (size_t)y * (size_t)d->stride;
		for (uint32_t x = 0; x < d->width; x++)
			n += depth_at(d, row, x) > 0;
	}
	return n;
}

static int write_vertices(FILE *fp, const struct dao_camera *cam, const struct dao_frame *d,
			  const struct dao_frame *ao)
{
	uint8_t buf[VERTICES_PER_WRITE * VERTEX_AO];
	const size_t size = ao ? VERTEX_AO : VERTEX_XYZ;
	size_t n = 0;
	for (uint32_t y = 0; y < d->height; y++) {
		const uint8_t *row = (const uint8_t *)d->data + (size_t)y * (size_t)d->stride;
		const uint8_t *arow = ao ? (const uint8_t *)ao->data + (size_t)y * (size_t)ao->stride
					 : NULL;
		for (uint32_t x = 0; x < d->width; x++) {
			double z = depth_at(d, row, x);
			if (!(z > 0))
				continue;
			double p[3];
			dao_camera_pixel_to_view(cam, x, y, z, p);
			uint8_t *o = buf + n * size;
			o = put_f32(o, (float)p[0]);
			o = put_f32(o, (float)p[1]);
			o = put_f32(o, (float)p[2]);
			if (ao) {
				float v = visibility_at(ao, arow, x);
				uint8_t g = (uint8_t)lrintf(v * 255.0f);
				o[0] = o[1] = o[2] = g;
				put_f32(o + 3, v);
			}
			if (++n == VERTICES_PER_WRITE) {
				if (fwrite(buf, size, n, fp) != n)
					return -1;
				n = 0;
			}
		}
	}
	return n && fwrite(buf, size, n, fp) != n ? -1 : 0;
}

int dao_ply_write(const char *path, const struct dao_camera *cam, const struct dao_frame *depth,
		  const struct dao_frame *ao, uint64_t *points, struct dao_error *err)
{
	int r = checked_inputs(path, cam, depth, ao, err);
	if (r)
		return r;
	const uint64_t count = count_points(depth);
	struct dao_output_file out;
	if ((r = dao_output_file_begin(&out, path, err)) < 0)
		return r;
	FILE *fp = fdopen(out.fd, "wb");
	if (!fp) {
		r = dao_error_set(err, -errno, "cannot write '%s': %s", path, strerror(errno));
		close(out.fd);
		dao_output_file_abandon(&out);
		return r;
	}
	errno = 0;
	int bad = fprintf(fp,
			  "ply\n"
			  "format binary_little_endian 1.0\n"
			  "comment depthao %s: optical frame (x right, y down, z forward), metres\n"
			  "element vertex %llu\n"
			  "property float x\n"
			  "property float y\n"
			  "property float z\n",
			  dao_version(), (unsigned long long)count) < 0;
	if (!bad && ao)
		bad = fputs("comment ao: visibility in [0, 1], 1 = open; the colour is its grey\n"
			    "property uchar red\n"
			    "property uchar green\n"
			    "property uchar blue\n"
			    "property float scalar_ao\n", fp) < 0;
	if (!bad)
		bad = fputs("end_header\n", fp) < 0 || write_vertices(fp, cam, depth, ao) ||
		      fflush(fp) != 0 || ferror(fp);
	int e = errno ? errno : EIO;
	int closed = fclose(fp);
	if (!bad && closed != 0) {
		bad = 1;
		e = errno ? errno : EIO;
	}
	if (bad) {
		dao_output_file_abandon(&out);
		return dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
	}
	if ((r = dao_output_file_finish(&out, path, err)) < 0)
		return r;
	if (points)
		*points = count;
	return 0;
}
