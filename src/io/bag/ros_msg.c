/* SPDX-License-Identifier: MIT */
/* Deserializing sensor_msgs/Image, CameraInfo, Imu, std_msgs/Float32, tf2_msgs/TFMessage
 * and nav_msgs/Odometry. */
#include "bag/ros_msg.h"

#include <errno.h>
#include <string.h>

struct cursor {
	const uint8_t *p;
	uint32_t left;
	int bad;
};

static const uint8_t *take(struct cursor *c, uint32_t n)
{
	if (c->bad || n > c->left) {
		c->bad = 1;
		return NULL;
	}
	const uint8_t *p = c->p;
	c->p += n;
	c->left -= n;
	return p;
}

static uint32_t u32(struct cursor *c)
{
	const uint8_t *p = take(c, 4);
	return p ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
			   (uint32_t)p[3] << 24
		 : 0;
}

static double f64(struct cursor *c)
{
	const uint8_t *p = take(c, 8);
	uint64_t v = 0;
	double d;
	for (int i = 7; p && i >= 0; i--)
		v = v << 8 | p[i];
	memcpy(&d, &v, sizeof(d));
	return d;
}

/* A string or uint8[]: its bytes, *n its length. */
static const uint8_t *bytes(struct cursor *c, uint32_t *n)
{
	*n = u32(c);
	return take(c, *n);
}

static void header(struct cursor *c, struct dao_ros_header *h)
{
	h->seq = u32(c);
	uint64_t sec = u32(c);
	h->stamp_ns = sec * 1000000000u + u32(c);
	h->frame_id = (const char *)bytes(c, &h->frame_id_len);
}

int dao_ros_image_parse(const uint8_t *msg, uint32_t len, struct dao_ros_image *img)
{
	struct cursor c = {msg, len, 0};
	uint32_t n;
	memset(img, 0, sizeof(*img));
	header(&c, &img->header);
	img->height = u32(&c);
	img->width = u32(&c);
	const uint8_t *enc = bytes(&c, &n);
	if (enc && n < sizeof(img->encoding) && !memchr(enc, 0, n))
		memcpy(img->encoding, enc, n);
	else
		c.bad = 1;
	const uint8_t *be = take(&c, 1);
	img->is_bigendian = be ? be[0] : 0;
	img->step = u32(&c);
	img->data = bytes(&c, &img->data_len);
	return c.bad ? -EINVAL : 0;
}

int dao_ros_camera_info_parse(const uint8_t *msg, uint32_t len, struct dao_ros_camera_info *ci)
{
	struct cursor c = {msg, len, 0};
	uint32_t n;
	memset(ci, 0, sizeof(*ci));
	header(&c, &ci->header);
	ci->height = u32(&c);
	ci->width = u32(&c);
	(void)bytes(&c, &n); /* distortion_model */
	ci->distortion_count = u32(&c);
	if (ci->distortion_count > c.left / 8)
		return -EINVAL;
	for (uint32_t i = 0; i < ci->distortion_count; i++) {
		double v = f64(&c);
		if (i < DAO_ROS_MAX_DISTORTION)
			ci->d[i] = v;
	}
	for (int i = 0; i < 9; i++)
		ci->k[i] = f64(&c);
	for (int i = 0; i < 9; i++)
		ci->r[i] = f64(&c);
	for (int i = 0; i < 12; i++)
		ci->p[i] = f64(&c);
	return c.bad ? -EINVAL : 0; /* binning and roi follow: not needed */
}

int dao_ros_float32_parse(const uint8_t *msg, uint32_t len, float *value)
{
	if (len != 4)
		return -EINVAL;
	uint32_t v = (uint32_t)msg[0] | (uint32_t)msg[1] << 8 | (uint32_t)msg[2] << 16 |
		     (uint32_t)msg[3] << 24;
	memcpy(value, &v, sizeof(*value));
	return 0;
}

/* A Header's stamp and frame_id (its seq read past); a nanosecond field of 1e9 or more
 * marks the cursor bad. */
static void stamp_frame(struct cursor *c, uint64_t *stamp_ns, const char **frame, uint32_t *len)
{
	(void)u32(c); /* seq */
	uint64_t sec = u32(c);
	uint32_t nsec = u32(c);
	if (nsec >= 1000000000u)
		c->bad = 1;
	*stamp_ns = sec * 1000000000u + nsec;
	*frame = (const char *)bytes(c, len);
}

/* Header, child_frame_id, then a translation (or position) and a rotation: 0 or -EINVAL. */
static int stamped_pose(struct cursor *c, struct dao_tf_msg_transform *t)
{
	stamp_frame(c, &t->stamp_ns, &t->parent, &t->parent_len);
	t->child = (const char *)bytes(c, &t->child_len);
	for (int i = 0; i < 3; i++)
		t->tr.t[i] = f64(c);
	for (int i = 0; i < 4; i++)
		t->tr.q[i] = f64(c);
	return c->bad ? -EINVAL : 0;
}

int dao_ros_tf_parse(const uint8_t *msg, uint32_t len, dao_tf_msg_cb cb, void *user)
{
	for (int pass = 0; pass < 2; pass++) { /* check all, then deliver */
		struct cursor c = {msg, len, 0};
		uint32_t n = u32(&c);
		if (c.bad || n > c.left / 76) /* a TransformStamped takes at least 76 bytes */
			return -EINVAL;
		for (uint32_t i = 0; i < n; i++) {
			struct dao_tf_msg_transform t;
			if (stamped_pose(&c, &t) < 0)
				return -EINVAL;
			int r = pass ? cb(user, &t) : 0;
			if (r < 0)
				return r;
		}
		if (c.left)
			return -EINVAL;
	}
	return 0;
}

int dao_ros_odometry_parse(const uint8_t *msg, uint32_t len, struct dao_tf_msg_transform *out)
{
	struct cursor c = {msg, len, 0};
	memset(out, 0, sizeof(*out));
	if (stamped_pose(&c, out) < 0)
		return -EINVAL;
	(void)take(&c, 8 * (36 + 6 + 36)); /* covariance, twist, its covariance */
	return c.bad || c.left ? -EINVAL : 0;
}

int dao_ros_imu_parse(const uint8_t *msg, uint32_t len, struct dao_imu_msg *out)
{
	struct cursor c = {msg, len, 0};
	memset(out, 0, sizeof(*out));
	stamp_frame(&c, &out->stamp_ns, &out->frame, &out->frame_len);
	for (int i = 0; i < 4; i++)
		out->q[i] = f64(&c);
	out->has_orientation = f64(&c) != -1.0;
	(void)take(&c, 8 * 8); /* the rest of the orientation's covariance */
	for (int i = 0; i < 3; i++)
		out->w[i] = f64(&c);
	(void)take(&c, 8 * (9 + 3 + 9)); /* covariance, linear_acceleration, covariance */
	return c.bad || c.left ? -EINVAL : 0;
}
