/* SPDX-License-Identifier: MIT */
/*
 * Pinhole camera in the optical frame (x right, y down, z forward, metres).
 *
 * Pixel (u, v) has its centre at integer coordinates.  A view position is an
 * affine function of the pixel times the depth z (UvToViewParams):
 *     x = (u * ax + bx) * z,   y = (v * ay + by) * z
 * with ax = 1/fx, bx = -cx/fx, ay = 1/fy, by = -cy/fy, precomputed once.
 */
#ifndef DEPTHAO_CAMERA_H
#define DEPTHAO_CAMERA_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * A pinhole camera: intrinsics and the UvToViewParams derived from them.
 *
 * Made by dao_camera_from_intrinsics(), _from_fov() or _from_camera_info(),
 * which set `size` to the program's sizeof (docs/abi.md: fields are only
 * appended; the library reads a field added after the first layout only when
 * `size` covers it, and a camera with size 0, made by hand, as the first
 * layout).
 */
struct dao_camera {
	uint32_t size;           /* sizeof(struct dao_camera) of the program, set by the makers */
	uint32_t width, height;  /* image size in pixels */
	double fx, fy, cx, cy;   /* intrinsics in pixels */
	float ax, ay, bx, by;    /* UvToViewParams, derived */
};

/* The smallest plausible focal length is the image's larger side divided by
 * this (a field of view of about 179 degrees; dao_camera_from_intrinsics). */
#define DAO_CAMERA_FOCAL_MIN_DIV 200
/* The largest plausible focal length is the image's larger side times this (a
 * field of view of about 0.03 degrees; dao_camera_from_intrinsics). */
#define DAO_CAMERA_FOCAL_MAX_MUL 1000

/*
 * Sets up a camera from intrinsics (pixels).  They must be plausible for the
 * image: fx, fy finite, from max(width, height) / DAO_CAMERA_FOCAL_MIN_DIV to
 * max(width, height) * DAO_CAMERA_FOCAL_MAX_MUL (a field of view of about
 * 0.03 to 179 degrees); cx in -width..2*width, cy in -height..2*height (at
 * most one image size outside the image); width and height in
 * 1..DAO_MAX_DIMENSION.  Returns 0 or -EINVAL with a message naming the
 * value.  Every camera the library makes (from a field of view, a
 * CameraInfo) passes this check.
 * The _sized functions take the caller's sizeof(struct dao_camera) (for
 * bindings): they write no byte past it, set cam->size to what they filled,
 * and refuse (-EINVAL) a size smaller than the first layout's.  Programs
 * call the inline functions without _sized.
 */
DAO_API int dao_camera_from_intrinsics_sized(struct dao_camera *cam, size_t size, uint32_t width,
					    uint32_t height, double fx, double fy, double cx,
					    double cy, struct dao_error *err);
/* dao_camera_from_intrinsics_sized() for this program's struct dao_camera. */
static inline int dao_camera_from_intrinsics(struct dao_camera *cam, uint32_t width,
					     uint32_t height, double fx, double fy, double cx,
					     double cy, struct dao_error *err)
{
	return dao_camera_from_intrinsics_sized(cam, sizeof(*cam), width, height, fx, fy, cx, cy,
						err);
}

/*
 * Sets up a camera from horizontal and vertical field of view (radians, in
 * (0, pi)), as OpenNI reports them: fx = (w/2) / tan(hfov/2),
 * cx = (w-1)/2, and the same for y.
 */
DAO_API int dao_camera_from_fov_sized(struct dao_camera *cam, size_t size, uint32_t width,
				     uint32_t height, double hfov, double vfov,
				     struct dao_error *err);
/* dao_camera_from_fov_sized() for this program's struct dao_camera. */
static inline int dao_camera_from_fov(struct dao_camera *cam, uint32_t width, uint32_t height,
				      double hfov, double vfov, struct dao_error *err)
{
	return dao_camera_from_fov_sized(cam, sizeof(*cam), width, height, hfov, vfov, err);
}

/* Which of a CameraInfo's matrices dao_camera_from_camera_info() took. */
enum dao_camera_info_matrix {
	DAO_CAMERA_INFO_K = 0,           /* no distortion: K, the camera matrix */
	DAO_CAMERA_INFO_K_DISTORTED = 1, /* distortion and no usable P: K */
	DAO_CAMERA_INFO_P_RECTIFIED = 2, /* distortion: P, the rectified image's camera */
};

/*
 * Sets up a camera from a ROS sensor_msgs/CameraInfo (REP 104; also its YAML
 * file): k[9] and p[12] row-major (p may be NULL: none), d[d_count] the
 * distortion coefficients (d may be NULL when d_count is 0).  K is the camera
 * of the raw (distorted) image, P that of the rectified one.  Without
 * distortion (every coefficient 0) K's intrinsics; with distortion P's when
 * P is usable (fx, fy > 0, fx, fy, cx, cy finite), as ROS's image_geometry
 * projects, else K's.  depthao does not undistort: with distortion the depth
 * must be rectified (an image_rect topic) for the camera to fit it, which the
 * caller should say (*from, when not NULL, tells which matrix was taken).
 * Returns 0, or -EINVAL with a message naming the matrix (K's focal length
 * not > 0, a value not finite, a size out of range).
 */
DAO_API int dao_camera_from_camera_info_sized(struct dao_camera *cam, size_t size,
					      uint32_t width, uint32_t height, const double k[9],
					      const double p[12], const double *d, size_t d_count,
					      enum dao_camera_info_matrix *from,
					      struct dao_error *err);
/* dao_camera_from_camera_info_sized() for this program's struct dao_camera. */
static inline int dao_camera_from_camera_info(struct dao_camera *cam, uint32_t width,
					      uint32_t height, const double k[9],
					      const double p[12], const double *d, size_t d_count,
					      enum dao_camera_info_matrix *from,
					      struct dao_error *err)
{
	return dao_camera_from_camera_info_sized(cam, sizeof(*cam), width, height, k, p, d,
						 d_count, from, err);
}

/* Field of view (radians) of a camera: hfov = 2 atan(w / (2 fx)). */
DAO_API void dao_camera_fov(const struct dao_camera *cam, double *hfov, double *vfov);

/* Pixel (u, v) at depth z -> view position p[3] (double precision, for tools). */
DAO_API void dao_camera_pixel_to_view(const struct dao_camera *cam, double u, double v, double z,
				      double p[3]);

/*
 * View position -> pixel.  Returns 0, or -EDOM when p is not in front of the
 * camera (z <= 0 or not finite).
 */
DAO_API int dao_camera_view_to_pixel(const struct dao_camera *cam, const double p[3],
				     double *u, double *v);

#ifdef __cplusplus
}
#endif
#endif
