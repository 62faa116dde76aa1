/* SPDX-License-Identifier: MIT */
/* ROS 2 messages in CDR for the MCAP sink (ros2_encode.h). */
#include "mcap/ros2_encode.h"

#include <string.h>

#include "mcap/mcap_format.h"

#define SEP "================================================================================\n"
#define TIME_MSG SEP "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"
#define HEADER_MSG SEP "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n"

const char dao_ros2_image_schema[] =
	"std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n"
	"uint8 is_bigendian\nuint32 step\nuint8[] data\n" HEADER_MSG TIME_MSG;

const char dao_ros2_camera_info_schema[] =
	"std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n"
	"float64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\n"
	"uint32 binning_y\nsensor_msgs/RegionOfInterest roi\n" HEADER_MSG TIME_MSG SEP
	"MSG: sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\n"
	"uint32 width\nbool do_rectify\n";

const char dao_ros2_point_cloud2_schema[] =
	"std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\n"
	"bool is_bigendian\nuint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n"
	HEADER_MSG TIME_MSG SEP
	"MSG: sensor_msgs/PointField\nuint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\n"
	"uint8 INT32=5\nuint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\n"
	"uint32 offset\nuint8 datatype\nuint32 count\n";

const char dao_ros2_tf_schema[] =
	"geometry_msgs/TransformStamped[] transforms\n" SEP
	"MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
	"Transform transform\n" HEADER_MSG TIME_MSG SEP
	"MSG: geometry_msgs/Transform\nVector3 translation\nQuaternion rotation\n" SEP
	"MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n" SEP
	"MSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";

/* A CDR writer; with base NULL it only counts. `at` counts from after the 4-byte
 * encapsulation header, as alignment does. */
struct cdrw {
	uint8_t *base;
	size_t at;
};

static void align(struct cdrw *c, size_t a)
{
	size_t to = (c->at + a - 1) & ~(a - 1);
	if (c->base && to > c->at)
		memset(c->base + c->at, 0, to - c->at);
	c->at = to;
}

static void u8(struct cdrw *c, uint8_t v)
{
	if (c->base)
		c->base[c->at] = v;
	c->at++;
}

static void u32(struct cdrw *c, uint32_t v)
{
	align(c, 4);
	if (c->base)
		dao_mcap_wr32(c->base + c->at, v);
	c->at += 4;
}

static void f64(struct cdrw *c, double v)
{
	uint64_t b;
	memcpy(&b, &v, 8);
	align(c, 8);
	if (c->base)
		dao_mcap_wr64(c->base + c->at, b);
	c->at += 8;
}

static void str(struct cdrw *c, const char *s)
{
	size_t n = strlen(s) + 1;
	u32(c, (uint32_t)n);
	if (c->base)
		memcpy(c->base + c->at, s, n);
	c->at += n;
}

static struct cdrw begin(uint8_t *out)
{
	if (out) {
		out[0] = 0;
		out[1] = 1; /* CDR_LE */
		out[2] = out[3] = 0;
	}
	return (struct cdrw){out ? out + 4 : NULL, 0};
}

static void header(struct cdrw *c, uint64_t ns, const char *frame_id)
{
	u32(c, (uint32_t)(ns / 1000000000u)); /* int32 sec: until 2038 */
	u32(c, (uint32_t)(ns % 1000000000u));
	str(c, frame_id);
}

static size_t image(uint8_t *out, uint64_t ns, const char *frame_id, const char *encoding,
		    const struct dao_frame *img)
{
	struct cdrw c = begin(out);
	size_t row = (size_t)img->width * dao_pixfmt_bytes_per_pixel(img->format);
	header(&c, ns, frame_id);
	u32(&c, img->height);
	u32(&c, img->width);
	str(&c, encoding);
	u8(&c, 0);
	u32(&c, (uint32_t)row);
	u32(&c, (uint32_t)(row * img->height));
	if (c.base) {
		const uint8_t *src = img->data;
		for (uint32_t y = 0; y < img->height; y++)
			memcpy(c.base + c.at + y * row, src + (size_t)y * (size_t)img->stride, row);
	}
	c.at += row * img->height;
	return 4 + c.at;
}

size_t dao_ros2_image_size(const char *frame_id, const char *encoding, const struct dao_frame *img)
{
	return image(NULL, 0, frame_id, encoding, img);
}

void dao_ros2_image_encode(uint8_t *out, uint64_t stamp_ns, const char *frame_id,
			   const char *encoding, const struct dao_frame *img)
{
	image(out, stamp_ns, frame_id, encoding, img);
}

static size_t camera_info(uint8_t *out, uint64_t ns, const char *frame_id,
			  const struct dao_ros2_pinhole *k)
{
	struct cdrw c = begin(out);
	header(&c, ns, frame_id);
	u32(&c, k ? k->height : 0);
	u32(&c, k ? k->width : 0);
	str(&c, "plumb_bob");
	u32(&c, 5);
	for (int i = 0; i < 5; i++)
		f64(&c, 0);
	double fx = k ? k->fx : 0, fy = k ? k->fy : 0, cx = k ? k->cx : 0, cy = k ? k->cy : 0;
	const double K[9] = {fx, 0, cx, 0, fy, cy, 0, 0, 1};
	const double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
	const double P[12] = {fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0};
	for (int i = 0; i < 9; i++)
		f64(&c, K[i]);
	for (int i = 0; i < 9; i++)
		f64(&c, R[i]);
	for (int i = 0; i < 12; i++)
		f64(&c, P[i]);
	for (int i = 0; i < 6; i++) /* binning x, y; roi x_offset, y_offset, height, width */
		u32(&c, 0);
	u8(&c, 0); /* roi.do_rectify */
	return 4 + c.at;
}

size_t dao_ros2_camera_info_size(const char *frame_id)
{
	return camera_info(NULL, 0, frame_id, NULL);
}

void dao_ros2_camera_info_encode(uint8_t *out, uint64_t stamp_ns, const char *frame_id,
				 const struct dao_ros2_pinhole *cam)
{
	camera_info(out, stamp_ns, frame_id, cam);
}

/* Everything of the cloud; the points' place (NULL when counting) through *points. */
static size_t cloud(uint8_t *out, uint64_t ns, const char *frame_id, uint32_t n, uint8_t **points)
{
	static const char *const names[4] = {"x", "y", "z", "ao"};
	struct cdrw c = begin(out);
	header(&c, ns, frame_id);
	u32(&c, 1);
	u32(&c, n);
	u32(&c, 4);
	for (uint32_t i = 0; i < 4; i++) {
		str(&c, names[i]);
		u32(&c, 4 * i);
		u8(&c, 7); /* FLOAT32 */
		u32(&c, 1);
	}
	u8(&c, 0); /* little-endian */
	u32(&c, DAO_ROS2_CLOUD_POINT_STEP);
	u32(&c, DAO_ROS2_CLOUD_POINT_STEP * n);
	u32(&c, DAO_ROS2_CLOUD_POINT_STEP * n);
	*points = c.base ? c.base + c.at : NULL;
	c.at += (size_t)DAO_ROS2_CLOUD_POINT_STEP * n;
	u8(&c, 1); /* is_dense: only points with depth */
	return 4 + c.at;
}

size_t dao_ros2_cloud_size(const char *frame_id, uint32_t npoints)
{
	uint8_t *p;
	return cloud(NULL, 0, frame_id, npoints, &p);
}

uint8_t *dao_ros2_cloud_encode(uint8_t *out, uint64_t stamp_ns, const char *frame_id,
			       uint32_t npoints)
{
	uint8_t *p;
	cloud(out, stamp_ns, frame_id, npoints, &p);
	return p;
}

static size_t tf(uint8_t *out, uint64_t ns, const char *parent, const char *child,
		 const double q[4], const double t[3])
{
	struct cdrw c = begin(out);
	u32(&c, 1); /* one TransformStamped */
	header(&c, ns, parent);
	str(&c, child);
	for (int i = 0; i < 3; i++)
		f64(&c, t ? t[i] : 0);
	for (int i = 0; i < 4; i++)
		f64(&c, q ? q[i] : 0);
	return 4 + c.at;
}

size_t dao_ros2_tf_size(const char *parent, const char *child)
{
	return tf(NULL, 0, parent, child, NULL, NULL);
}

void dao_ros2_tf_encode(uint8_t *out, uint64_t stamp_ns, const char *parent, const char *child,
			const double q[4], const double t[3])
{
	tf(out, stamp_ns, parent, child, q, t);
}
