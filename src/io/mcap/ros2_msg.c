/* SPDX-License-Identifier: MIT */
/* ROS 2 messages in CDR (ros2_msg.h). */
#include "mcap/ros2_msg.h"

#include <errno.h>
#include <string.h>

#include "mcap/cdr.h"

static void header(struct dao_cdr *c, struct dao_ros2_header *h)
{
	int32_t sec = dao_cdr_i32(c);
	uint32_t nsec = dao_cdr_u32(c);
	h->frame_id = dao_cdr_string(c, &h->frame_id_len);
	h->stamp_ns = sec < 0 ? 0 : (uint64_t)sec * 1000000000u + nsec;
}

/* The reader on msg, and *out (size bytes) zeroed: 0 or dao_cdr_init's error. */
static int start(struct dao_cdr *c, const uint8_t *msg, uint64_t len, void *out, size_t size)
{
	memset(out, 0, size);
	return dao_cdr_init(c, msg, len > SIZE_MAX ? SIZE_MAX : (size_t)len);
}

int dao_ros2_image_parse(const uint8_t *msg, uint64_t len, struct dao_ros2_image *img)
{
	struct dao_cdr c;
	int r = start(&c, msg, len, img, sizeof(*img));
	if (r < 0)
		return r;
	header(&c, &img->header);
	img->height = dao_cdr_u32(&c);
	img->width = dao_cdr_u32(&c);
	dao_cdr_string_copy(&c, img->encoding, sizeof img->encoding);
	img->is_bigendian = dao_cdr_u8(&c);
	img->step = dao_cdr_u32(&c);
	img->data_len = dao_cdr_seq(&c, 1);
	img->data = dao_cdr_bytes(&c, img->data_len);
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}

int dao_ros2_compressed_image_parse(const uint8_t *msg, uint64_t len,
				    struct dao_ros2_compressed_image *img)
{
	struct dao_cdr c;
	int r = start(&c, msg, len, img, sizeof(*img));
	if (r < 0)
		return r;
	header(&c, &img->header);
	dao_cdr_string_copy(&c, img->format, sizeof img->format);
	img->data_len = dao_cdr_seq(&c, 1);
	img->data = dao_cdr_bytes(&c, img->data_len);
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}

/* A CameraInfo's or CameraCalibration's D (float64[]: the first dmax kept), K, R
 * (float64[9]) and P (float64[12]) read into d, k, r, p: D's count. */
static uint32_t camera_matrices(struct dao_cdr *c, double *d, uint32_t dmax, double k[9],
			    double r[9], double p[12])
{
	uint32_t n = dao_cdr_seq(c, 8);
	for (uint32_t i = 0; i < n; i++) {
		double v = dao_cdr_f64(c);
		if (i < dmax)
			d[i] = v;
	}
	for (int i = 0; i < 9; i++)
		k[i] = dao_cdr_f64(c);
	for (int i = 0; i < 9; i++)
		r[i] = dao_cdr_f64(c);
	for (int i = 0; i < 12; i++)
		p[i] = dao_cdr_f64(c);
	return n;
}

int dao_ros2_camera_info_parse(const uint8_t *msg, uint64_t len, struct dao_ros2_camera_info *ci)
{
	struct dao_cdr c;
	int r = start(&c, msg, len, ci, sizeof(*ci));
	if (r < 0)
		return r;
	header(&c, &ci->header);
	ci->height = dao_cdr_u32(&c);
	ci->width = dao_cdr_u32(&c);
	dao_cdr_string_copy(&c, ci->distortion_model, sizeof ci->distortion_model);
	ci->distortion_count =
		camera_matrices(&c, ci->d, DAO_ROS2_MAX_DISTORTION, ci->k, ci->r, ci->p);
	/* binning_x, binning_y, roi (x_offset, y_offset, height, width, do_rectify): not used */
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}

/* A builtin_interfaces/Time (a Header's stamp) and the frame_id after it: 0 or -EINVAL. */
static int stamp_and_frame(struct dao_cdr *c, uint64_t *stamp_ns, const char **frame,
			   uint32_t *len)
{
	int32_t sec = dao_cdr_i32(c);
	uint32_t nsec = dao_cdr_u32(c);
	if (sec < 0 || nsec >= 1000000000u)
		return -EINVAL;
	*stamp_ns = (uint64_t)sec * 1000000000u + nsec;
	*frame = dao_cdr_string(c, len);
	return 0;
}

static int stamp_frame(struct dao_cdr *c, struct dao_tf_msg_transform *t)
{
	return stamp_and_frame(c, &t->stamp_ns, &t->parent, &t->parent_len);
}

/* A translation (or position) and a rotation. */
static int rigid(struct dao_cdr *c, struct dao_tf_msg_transform *t)
{
	for (int i = 0; i < 3; i++)
		t->tr.t[i] = dao_cdr_f64(c);
	for (int i = 0; i < 4; i++)
		t->tr.q[i] = dao_cdr_f64(c);
	return dao_cdr_ok(c) ? 0 : -EINVAL;
}

/* Header, child_frame_id, a translation (or position) and a rotation: 0 or -EINVAL. */
static int stamped_pose(struct dao_cdr *c, struct dao_tf_msg_transform *t)
{
	if (stamp_frame(c, t) < 0)
		return -EINVAL;
	t->child = dao_cdr_string(c, &t->child_len);
	return rigid(c, t);
}

int dao_ros2_tf_parse(const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb, void *user)
{
	for (int pass = 0; pass < 2; pass++) { /* check all, then deliver */
		struct dao_cdr c;
		int r = dao_cdr_init(&c, msg, len > SIZE_MAX ? SIZE_MAX : (size_t)len);
		if (r < 0)
			return r;
		uint32_t n = dao_cdr_seq(&c, 72); /* a TransformStamped takes at least 72 bytes */
		for (uint32_t i = 0; i < n && dao_cdr_ok(&c); i++) {
			struct dao_tf_msg_transform t;
			if (stamped_pose(&c, &t) < 0)
				return -EINVAL;
			if (pass && (r = cb(user, &t)) < 0)
				return r;
		}
		if (!dao_cdr_ok(&c))
			return -EINVAL;
	}
	return 0;
}

int dao_ros2_odometry_parse(const uint8_t *msg, uint64_t len, struct dao_tf_msg_transform *out)
{
	struct dao_cdr c;
	int r = start(&c, msg, len, out, sizeof(*out));
	if (r < 0)
		return r;
	if (stamped_pose(&c, out) < 0)
		return -EINVAL;
	for (int i = 0; i < 36 + 6 + 36; i++) /* covariance, twist, its covariance */
		(void)dao_cdr_f64(&c);
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}

int dao_ros2_imu_parse(const uint8_t *msg, uint64_t len, struct dao_imu_msg *out)
{
	struct dao_cdr c;
	int r = start(&c, msg, len, out, sizeof(*out));
	if (r < 0)
		return r;
	if (stamp_and_frame(&c, &out->stamp_ns, &out->frame, &out->frame_len) < 0)
		return -EINVAL;
	for (int i = 0; i < 4; i++)
		out->q[i] = dao_cdr_f64(&c);
	out->has_orientation = dao_cdr_f64(&c) != -1.0;
	for (int i = 1; i < 9; i++) /* the rest of the orientation's covariance */
		(void)dao_cdr_f64(&c);
	for (int i = 0; i < 3; i++)
		out->w[i] = dao_cdr_f64(&c);
	for (int i = 0; i < 9 + 3 + 9; i++) /* covariance, linear_acceleration, covariance */
		(void)dao_cdr_f64(&c);
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}

int dao_ros2_fg_transform_parse(const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb, void *user)
{
	struct dao_cdr c;
	struct dao_tf_msg_transform t;
	int r = start(&c, msg, len, &t, sizeof(t));
	if (r < 0)
		return r;
	if (stamped_pose(&c, &t) < 0)
		return -EINVAL;
	return (r = cb(user, &t)) < 0 ? r : 0;
}

int dao_ros2_fg_pose_parse(int list, const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb,
			   void *user)
{
	struct dao_cdr c;
	struct dao_tf_msg_transform t;
	int r = start(&c, msg, len, &t, sizeof(t));
	if (r < 0)
		return r;
	t.child = "";
	if (stamp_frame(&c, &t) < 0)
		return -EINVAL;
	uint32_t n = list ? dao_cdr_seq(&c, 56) : 1; /* a Pose: 7 float64 */
	if (!dao_cdr_ok(&c))
		return -EINVAL;
	if (n != 1) /* which of them is the camera's is unknown */
		return -ERANGE;
	if (rigid(&c, &t) < 0)
		return -EINVAL;
	return (r = cb(user, &t)) < 0 ? r : 0;
}

/* A Foxglove message's timestamp (builtin_interfaces/Time) and frame_id (into dst, cap
 * bytes); the reader made bad by a nanosec out of range or a frame_id that does not fit. */
static uint64_t fg_stamp_frame(struct dao_cdr *c, char *dst, size_t cap)
{
	int32_t sec = dao_cdr_i32(c);
	uint32_t nsec = dao_cdr_u32(c);
	if (nsec >= 1000000000u)
		c->bad = 1;
	dao_cdr_string_copy_strict(c, dst, cap);
	return sec < 0 || c->bad ? 0 : (uint64_t)sec * 1000000000u + nsec;
}

int dao_ros2_fg_image_parse(int compressed, const uint8_t *msg, uint64_t len,
			    struct dao_fg_image *img)
{
	struct dao_cdr c;
	int r = start(&c, msg, len, img, sizeof(*img));
	if (r < 0)
		return r;
	img->stamp_ns = fg_stamp_frame(&c, img->frame_id, sizeof img->frame_id);
	if (!compressed) {
		img->width = dao_cdr_u32(&c);
		img->height = dao_cdr_u32(&c);
		dao_cdr_string_copy_strict(&c, img->encoding, sizeof img->encoding);
		img->step = dao_cdr_u32(&c);
	}
	img->data_len = dao_cdr_seq(&c, 1);
	img->data = dao_cdr_bytes(&c, img->data_len);
	if (compressed)
		dao_cdr_string_copy_strict(&c, img->encoding, sizeof img->encoding); /* format */
	if (!dao_cdr_ok(&c)) {
		img->data = NULL;
		img->data_len = 0;
		return -EINVAL;
	}
	return 0;
}

int dao_ros2_fg_calibration_parse(const uint8_t *msg, uint64_t len,
				  struct dao_fg_calibration *cal)
{
	struct dao_cdr c;
	char text[256];
	int r = start(&c, msg, len, cal, sizeof(*cal));
	if (r < 0)
		return r;
	cal->stamp_ns = fg_stamp_frame(&c, text, sizeof text);
	cal->width = dao_cdr_u32(&c);
	cal->height = dao_cdr_u32(&c);
	dao_cdr_string_copy_strict(&c, text, sizeof text); /* distortion_model */
	cal->d_count = camera_matrices(&c, cal->d, DAO_FG_MAX_DISTORTION, cal->k, cal->r, cal->p);
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}
