/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_FOXGLOVE_MSG_H
#define DAO_MCAP_FOXGLOVE_MSG_H

/*
 * Foxglove's image schemas (github.com/foxglove/schemas), the messages an
 * MCAP file written by Foxglove's SDKs holds, in their protobuf encoding
 * (protobuf.h; the official .proto field numbers below) or their JSON one
 * (an object of the fields by name; bytes in base64, a timestamp as
 * {"sec", "nsec"}):
 *   foxglove.RawImage: timestamp 1, frame_id 7, width 2 (fixed32), height 3
 *     (fixed32), encoding 4, step 5 (fixed32), data 6;
 *   foxglove.CompressedImage: timestamp 1, frame_id 4, data 2, format 3;
 *   foxglove.CameraCalibration: timestamp 1, frame_id 9, width 2 (fixed32),
 *     height 3 (fixed32), distortion_model 4, D 5, K 6, R 7, P 8 (repeated
 *     double, packed or not).
 *   foxglove.FrameTransform: timestamp 1, parent_frame_id 2,
 *     child_frame_id 3, translation 4 (foxglove.Vector3: x 1, y 2, z 3,
 *     double), rotation 5 (foxglove.Quaternion: x 1, y 2, z 3, w 4, double);
 *   foxglove.FrameTransforms: transforms 1 (repeated FrameTransform);
 *   foxglove.PoseInFrame: timestamp 1, frame_id 2, pose 3 (foxglove.Pose:
 *     position 1, a Vector3, orientation 2, a Quaternion);
 *   foxglove.PosesInFrame: timestamp 1, frame_id 2, poses 3 (repeated Pose).
 * The timestamp is google.protobuf.Timestamp: seconds 1 (int64), nanos 2
 * (int32).  Pixels are little-endian (RawImage has no byte-order field).
 * The same schemas as ROS 2 messages, foxglove_msgs/msg/NAME in CDR
 * (DAO_FG_CDR), are read by ros2_msg.c (their fields in order there) into
 * the same structs and callbacks, with the same rules.
 * The parsers return 0 or -EINVAL (a message that does not fit its type: a
 * field of the wrong type, a K without 9 values ...); -ENOMEM or -EFBIG when
 * the JSON's bytes do not fit the buffer's limit; -ENOTSUP for a CDR
 * encapsulation other than XCDR1.
 */
#include <stddef.h>
#include <stdint.h>

#include "tf/tf_msg.h"

/* DAO_FG_CDR: foxglove_msgs/msg/... in CDR (ros2_msg.h: dao_ros2_fg_*_parse,
 * dao_ros2_tf_parse for a FrameTransforms). */
enum dao_fg_encoding { DAO_FG_PROTOBUF, DAO_FG_JSON, DAO_FG_CDR };

/* foxglove.RawImage or foxglove.CompressedImage; data points into the
 * message (protobuf) or into the buffer (JSON). */
struct dao_fg_image {
	uint64_t stamp_ns;              /* 0 for a stamp before 1970 */
	char frame_id[256];             /* "" when the message has none */
	uint32_t width, height, step;   /* RawImage's */
	char encoding[64];              /* RawImage's encoding, CompressedImage's format */
	const uint8_t *data;
	size_t data_len;
};

#define DAO_FG_MAX_DISTORTION 16

struct dao_fg_calibration {
	uint64_t stamp_ns;
	uint32_t width, height;
	uint32_t d_count;               /* of D (the first DAO_FG_MAX_DISTORTION kept) */
	double d[DAO_FG_MAX_DISTORTION];
	double k[9], r[9], p[12];       /* P all 0 when the message has none */
};

/* Where the JSON encoding's base64 bytes are decoded: grows up to `max` bytes. */
struct dao_fg_buf {
	uint8_t *p;
	size_t cap, max;
};
void dao_fg_buf_free(struct dao_fg_buf *b);

int dao_fg_raw_image_parse(enum dao_fg_encoding enc, const uint8_t *msg, size_t len,
			   struct dao_fg_buf *buf, struct dao_fg_image *img);
int dao_fg_compressed_image_parse(enum dao_fg_encoding enc, const uint8_t *msg, size_t len,
				  struct dao_fg_buf *buf, struct dao_fg_image *img);
int dao_fg_calibration_parse(enum dao_fg_encoding enc, const uint8_t *msg, size_t len,
			     struct dao_fg_calibration *cal);

/*
 * foxglove.FrameTransform (list 0) or foxglove.FrameTransforms (list 1): the
 * whole message checked, then cb called for each transform in order (the
 * transform of child_frame_id in parent_frame_id at its timestamp).  As
 * Foxglove reads them: a field left out is 0 or "" (a timestamp left out is
 * 0), but a rotation left out is the identity.  The values are passed on
 * unchecked (dao_tf_buffer_add checks them); JSON numbers may be NaN or
 * Infinity, as json-c reads them.  The names point into the message
 * (protobuf) or into the parsed JSON, valid during the call only.  0,
 * -EINVAL (not the type: cut short, not JSON, a field of the wrong type,
 * nanoseconds out of range), or cb's value < 0, which stops it.
 */
int dao_fg_frame_transforms_parse(enum dao_fg_encoding enc, int list, const uint8_t *msg,
				  size_t len, dao_tf_msg_cb cb, void *user);

/*
 * foxglove.PoseInFrame (list 0) or foxglove.PosesInFrame (list 1): cb called
 * once with the pose as a transform of an empty child in frame_id at its
 * timestamp, after the message is checked, as dao_fg_frame_transforms_parse
 * (a pose left out is the identity, as is an orientation).  0, -EINVAL,
 * -ERANGE for a PosesInFrame of other than exactly one pose (which one is
 * the camera's is unknown), or cb's value < 0.
 */
int dao_fg_poses_parse(enum dao_fg_encoding enc, int list, const uint8_t *msg, size_t len,
		       dao_tf_msg_cb cb, void *user);

/* Standard base64 (RFC 4648, padding optional) of `len` chars into out (cap bytes): bytes or -1. */
long dao_base64_decode(const char *in, size_t len, uint8_t *out, size_t cap);

#endif
