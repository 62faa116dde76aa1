/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <string.h>

#include <depthao/camera.h>
#include <depthao/frame.h>

#include "core/error_internal.h"
#include "core/math_util.h"
#include "core/sized.h"

/* The first struct dao_camera that carried `size` (depthao 1.0): never changes. */
#define CAMERA_SIZE_FIRST DAO_END_OF(struct dao_camera, by)

/* The made camera `c` into the caller's of `size` bytes (core/sized.h). */
static int give(struct dao_camera *cam, size_t size, const struct dao_camera *c,
		struct dao_error *err)
{
	if (size < CAMERA_SIZE_FIRST)
		return dao_error_set(err, -EINVAL,
				     "struct dao_camera of %zu bytes is smaller than the first "
				     "layout (%zu): pass sizeof(struct dao_camera)",
				     size, (size_t)CAMERA_SIZE_FIRST);
	return dao_sized_copy_out(cam, size, c, sizeof(*c));
}

static int check_size(uint32_t w, uint32_t h, struct dao_error *err)
{
	if (w == 0 || h == 0 || w > DAO_MAX_DIMENSION || h > DAO_MAX_DIMENSION)
		return dao_error_set(err, -EINVAL,
				     "camera size %ux%u is out of range (1..%d pixels per side)", w,
				     h, DAO_MAX_DIMENSION);
	return 0;
}

/*
 * Plausible intrinsics for a w x h image: the one rule of every camera file,
 * CameraInfo and option.  Focal lengths between 1/200 and 1000 times the
 * image's larger side (a field of view from about 0.03 to 179 degrees across
 * it), the principal point no further than one image size outside the image.
 */
static int check_focal(const char *name, double f, uint32_t w, uint32_t h, struct dao_error *err)
{
	const double side = w > h ? w : h, lo = side / DAO_CAMERA_FOCAL_MIN_DIV,
		     hi = side * DAO_CAMERA_FOCAL_MAX_MUL;
	if (!isfinite(f) || !(f >= lo && f <= hi))
		return dao_error_set(err, -EINVAL,
				     "focal length %s=%g is implausible for %ux%u images: give "
				     "pixels, from %g to %g (fields of view of 0.03 to 179 "
				     "degrees)",
				     name, f, w, h, lo, hi);
	return 0;
}

static int check_center(const char *name, double c, uint32_t side, uint32_t w, uint32_t h,
			struct dao_error *err)
{
	if (!isfinite(c) || !(c >= -(double)side && c <= 2.0 * side))
		return dao_error_set(err, -EINVAL,
				     "principal point %s=%g is implausible for %ux%u images: give "
				     "pixels, from %d to %u (at most one image size outside)",
				     name, c, w, h, -(int)side, 2 * side);
	return 0;
}

static int check_intrinsics(uint32_t w, uint32_t h, double fx, double fy, double cx, double cy,
			    struct dao_error *err)
{
	int r;
	if ((r = check_focal("fx", fx, w, h, err)) || (r = check_focal("fy", fy, w, h, err)) ||
	    (r = check_center("cx", cx, w, w, h, err)) || (r = check_center("cy", cy, h, w, h, err)))
		return r;
	return 0;
}

int dao_camera_from_intrinsics_sized(struct dao_camera *cam, size_t size, uint32_t w, uint32_t h,
				     double fx, double fy, double cx, double cy,
				     struct dao_error *err)
{
	if (!cam)
		return dao_error_set(err, -EINVAL, "camera is NULL");
	int r = check_size(w, h, err);
	if (r)
		return r;
	if ((r = check_intrinsics(w, h, fx, fy, cx, cy, err)))
		return r;
	/* field by field over zeros: the padding after `height` is copied out too, and
	 * cameras made alike compare equal byte for byte */
	struct dao_camera c;
	memset(&c, 0, sizeof c);
	c.size = sizeof(struct dao_camera);
	c.width = w;
	c.height = h;
	c.fx = fx;
	c.fy = fy;
	c.cx = cx;
	c.cy = cy;
	/* UvToViewParams in pixel units: x = (u*ax + bx) z */
	c.ax = (float)(1.0 / fx);
	c.bx = (float)(-cx / fx);
	c.ay = (float)(1.0 / fy);
	c.by = (float)(-cy / fy);
	return give(cam, size, &c, err);
}

int dao_camera_from_fov_sized(struct dao_camera *cam, size_t size, uint32_t w, uint32_t h,
			      double hfov, double vfov, struct dao_error *err)
{
	int r = check_size(w, h, err);
	if (r)
		return r;
	if (!isfinite(hfov) || !isfinite(vfov) || hfov <= 0 || vfov <= 0 || hfov >= DAO_PI ||
	    vfov >= DAO_PI)
		return dao_error_set(err, -EINVAL,
				     "field of view %g x %g rad must be in (0, pi) (give degrees "
				     "converted to radians)", hfov, vfov);
	double fx = (w / 2.0) / tan(hfov / 2.0);
	double fy = (h / 2.0) / tan(vfov / 2.0);
	return dao_camera_from_intrinsics_sized(cam, size, w, h, fx, fy, (w - 1) / 2.0,
						(h - 1) / 2.0, err);
}

int dao_camera_from_camera_info_sized(struct dao_camera *cam, size_t size, uint32_t w, uint32_t h,
				      const double k[9], const double p[12], const double *d,
				      size_t d_count, enum dao_camera_info_matrix *from,
				      struct dao_error *err)
{
	if (!cam)
		return dao_error_set(err, -EINVAL, "camera is NULL");
	if (!k)
		return dao_error_set(err, -EINVAL, "the CameraInfo has no K (camera_matrix)");
	if (d_count && !d)
		return dao_error_set(err, -EINVAL, "the CameraInfo's %zu distortion coefficients "
				     "are missing (NULL)", d_count);
	int distorted = 0;
	for (size_t i = 0; i < d_count; i++)
		distorted |= d[i] != 0.0;
	enum dao_camera_info_matrix m = DAO_CAMERA_INFO_K;
	if (distorted)
		m = p && p[0] > 0 && p[5] > 0 && isfinite(p[0]) && isfinite(p[5]) &&
				    isfinite(p[2]) && isfinite(p[6])
			    ? DAO_CAMERA_INFO_P_RECTIFIED
			    : DAO_CAMERA_INFO_K_DISTORTED;
	/* K = [fx 0 cx; 0 fy cy; 0 0 1], P = [fx' 0 cx' Tx; 0 fy' cy' Ty; 0 0 1 0] */
	const int use_p = m == DAO_CAMERA_INFO_P_RECTIFIED;
	const double fx = use_p ? p[0] : k[0], fy = use_p ? p[5] : k[4];
	const double cx = use_p ? p[2] : k[2], cy = use_p ? p[6] : k[5];
	int r = check_size(w, h, err);
	if (r)
		return r;
	struct dao_error e;
	if ((r = dao_camera_from_intrinsics_sized(cam, size, w, h, fx, fy, cx, cy, &e)))
		return dao_error_set(err, r, "the CameraInfo's %s: %s",
				     use_p ? "P (projection_matrix)" : "K (camera_matrix)", e.message);
	if (from)
		*from = m;
	return 0;
}

void dao_camera_fov(const struct dao_camera *cam, double *hfov, double *vfov)
{
	if (hfov)
		*hfov = 2.0 * atan(cam->width / (2.0 * cam->fx));
	if (vfov)
		*vfov = 2.0 * atan(cam->height / (2.0 * cam->fy));
}

void dao_camera_pixel_to_view(const struct dao_camera *cam, double u, double v, double z,
			      double p[3])
{
	p[0] = (u - cam->cx) / cam->fx * z;
	p[1] = (v - cam->cy) / cam->fy * z;
	p[2] = z;
}

int dao_camera_view_to_pixel(const struct dao_camera *cam, const double p[3], double *u, double *v)
{
	if (!(p[2] > 0) || !isfinite(p[2]) || !isfinite(p[0]) || !isfinite(p[1]))
		return -EDOM;
	*u = cam->fx * (p[0] / p[2]) + cam->cx;
	*v = cam->fy * (p[1] / p[2]) + cam->cy;
	return 0;
}
