/* SPDX-License-Identifier: MIT */
/* Foxglove's image, transform and pose schemas in protobuf or JSON, and in CDR through
 * ros2_msg.c (foxglove_msg.h). */
#include "mcap/foxglove_msg.h"

#include <errno.h>
#include <json-c/json.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mcap/protobuf.h"
#include "mcap/ros2_msg.h"

/* Seconds past 1970 up to which a stamp in ns fits 64 bits, with room. */
#define MAX_SECONDS 10000000000LL

static uint64_t stamp_ns(int64_t sec, int64_t nsec, int *bad)
{
	if (nsec < 0 || nsec > 999999999 || sec > MAX_SECONDS) {
		*bad = 1;
		return 0;
	}
	return sec < 0 ? 0 : (uint64_t)sec * 1000000000u + (uint64_t)nsec;
}

/* ---- protobuf ---- */

/* A field holding a message (wire type LEN): 1 with s on its bytes, else 0 and r bad. */
static int pb_sub(struct dao_pb *r, uint32_t wire, struct dao_pb *s)
{
	size_t n;
	const uint8_t *p = wire == DAO_PB_LEN ? dao_pb_bytes(r, &n) : NULL;
	if (!p) {
		r->bad = 1;
		return 0;
	}
	dao_pb_init(s, p, n);
	return 1;
}

static uint64_t pb_timestamp(struct dao_pb *r, uint32_t wire)
{
	int64_t sec = 0, nsec = 0;
	struct dao_pb t;
	uint32_t f, w;
	if (!pb_sub(r, wire, &t))
		return 0;
	while (dao_pb_next(&t, &f, &w)) {
		if ((f == 1 || f == 2) && w == DAO_PB_VARINT) {
			uint64_t v = dao_pb_varint(&t);
			if (f == 1)
				sec = (int64_t)v;
			else
				nsec = (int32_t)(uint32_t)v;
		} else {
			dao_pb_skip(&t, w);
		}
	}
	if (t.bad)
		r->bad = 1;
	return stamp_ns(sec, nsec, &r->bad);
}

static uint32_t pb_u32(struct dao_pb *r, uint32_t wire)
{
	if (wire == DAO_PB_I32)
		return dao_pb_fixed32(r);
	r->bad = 1; /* the schemas' sizes are fixed32 */
	return 0;
}

static void pb_string(struct dao_pb *r, uint32_t wire, char *dst, size_t cap)
{
	size_t n;
	const uint8_t *p = wire == DAO_PB_LEN ? dao_pb_bytes(r, &n) : NULL;
	if (!p || n >= cap || memchr(p, 0, n)) {
		r->bad = 1;
		return;
	}
	memcpy(dst, p, n);
	dst[n] = 0;
}

static const uint8_t *pb_data(struct dao_pb *r, uint32_t wire, size_t *len)
{
	if (wire == DAO_PB_LEN)
		return dao_pb_bytes(r, len);
	r->bad = 1;
	return NULL;
}

/* A repeated double, packed (one LEN field) or not (I64 fields); count is updated. */
static void pb_doubles(struct dao_pb *r, uint32_t wire, double *dst, uint32_t cap,
		       uint32_t *count)
{
	if (wire == DAO_PB_I64) {
		double v = dao_pb_double(r);
		if (*count < cap)
			dst[*count] = v;
		*count += *count < UINT32_MAX;
		return;
	}
	size_t n;
	const uint8_t *p = wire == DAO_PB_LEN ? dao_pb_bytes(r, &n) : NULL;
	if (!p || n % 8) {
		r->bad = 1;
		return;
	}
	struct dao_pb s;
	dao_pb_init(&s, p, n);
	for (size_t i = 0; i < n / 8; i++) {
		double v = dao_pb_double(&s);
		if (*count < cap)
			dst[*count] = v;
		*count += *count < UINT32_MAX;
	}
}

static int pb_raw_image(const uint8_t *msg, size_t len, struct dao_fg_image *img)
{
	struct dao_pb r;
	uint32_t f, w;
	dao_pb_init(&r, msg, len);
	while (dao_pb_next(&r, &f, &w)) {
		switch (f) {
		case 1: img->stamp_ns = pb_timestamp(&r, w); break;
		case 2: img->width = pb_u32(&r, w); break;
		case 3: img->height = pb_u32(&r, w); break;
		case 4: pb_string(&r, w, img->encoding, sizeof img->encoding); break;
		case 5: img->step = pb_u32(&r, w); break;
		case 6: img->data = pb_data(&r, w, &img->data_len); break;
		case 7: pb_string(&r, w, img->frame_id, sizeof img->frame_id); break;
		default: dao_pb_skip(&r, w);
		}
	}
	return r.bad ? -EINVAL : 0;
}

static int pb_compressed_image(const uint8_t *msg, size_t len, struct dao_fg_image *img)
{
	struct dao_pb r;
	uint32_t f, w;
	dao_pb_init(&r, msg, len);
	while (dao_pb_next(&r, &f, &w)) {
		switch (f) {
		case 1: img->stamp_ns = pb_timestamp(&r, w); break;
		case 2: img->data = pb_data(&r, w, &img->data_len); break;
		case 3: pb_string(&r, w, img->encoding, sizeof img->encoding); break;
		case 4: pb_string(&r, w, img->frame_id, sizeof img->frame_id); break;
		default: dao_pb_skip(&r, w);
		}
	}
	return r.bad ? -EINVAL : 0;
}

/* A foxglove.Vector3 or foxglove.Quaternion (n doubles, fields 1..n) merged into v. */
static void pb_vector(struct dao_pb *r, uint32_t wire, double *v, uint32_t n)
{
	struct dao_pb s;
	uint32_t f, w;
	if (!pb_sub(r, wire, &s))
		return;
	while (dao_pb_next(&s, &f, &w)) {
		if (f >= 1 && f <= n && w == DAO_PB_I64)
			v[f - 1] = dao_pb_double(&s);
		else if (f >= 1 && f <= n)
			s.bad = 1; /* a component of another type */
		else
			dao_pb_skip(&s, w);
	}
	if (s.bad)
		r->bad = 1;
}

/* A name: its bytes in the message (a string field). */
static void pb_name(struct dao_pb *r, uint32_t wire, const char **name, uint32_t *len)
{
	size_t n = 0;
	const uint8_t *p = wire == DAO_PB_LEN ? dao_pb_bytes(r, &n) : NULL;
	if (!p || n > UINT32_MAX) {
		r->bad = 1;
		return;
	}
	*name = (const char *)p;
	*len = (uint32_t)n;
}

/* A foxglove.Quaternion into q: once present, its components are 0 unless given (a
 * rotation left out is the identity). */
static void pb_rotation(struct dao_pb *r, uint32_t wire, double *q, int *seen)
{
	if (!(*seen)++)
		q[3] = 0.0;
	pb_vector(r, wire, q, 4);
}

/* t all 0 and "", its rotation the identity: a message's fields left out. */
static void frame_transform_init(struct dao_tf_msg_transform *t)
{
	memset(t, 0, sizeof(*t));
	t->parent = t->child = "";
	t->tr.q[3] = 1.0;
}

/* foxglove.Pose: position 1 (Vector3), orientation 2 (Quaternion), merged into tr. */
static void pb_pose(struct dao_pb *r, uint32_t wire, struct dao_rigid *tr, int *rotation)
{
	struct dao_pb s;
	uint32_t f, w;
	if (!pb_sub(r, wire, &s))
		return;
	while (dao_pb_next(&s, &f, &w)) {
		if (f == 1)
			pb_vector(&s, w, tr->t, 3);
		else if (f == 2)
			pb_rotation(&s, w, tr->q, rotation);
		else
			dao_pb_skip(&s, w);
	}
	if (s.bad)
		r->bad = 1;
}

/*
 * foxglove.FrameTransform (list < 0: timestamp 1, parent_frame_id 2, child_frame_id 3,
 * translation 4, rotation 5), PoseInFrame (list 0: timestamp 1, frame_id 2 as the parent,
 * pose 3) or PosesInFrame (list 1: poses 3, repeated: the first into t, the others
 * checked) into t, *n the poses (1 but for a PosesInFrame).  Left out: 0, "", the identity.
 */
static int pb_framed(int list, const uint8_t *msg, size_t len, struct dao_tf_msg_transform *t,
		     uint32_t *n)
{
	struct dao_pb r;
	uint32_t f, w;
	int rotation = 0;
	frame_transform_init(t);
	*n = list != 1;
	dao_pb_init(&r, msg, len);
	while (dao_pb_next(&r, &f, &w)) {
		if (f == 1) {
			t->stamp_ns = pb_timestamp(&r, w);
		} else if (f == 2) {
			pb_name(&r, w, &t->parent, &t->parent_len);
		} else if (f == 3 && list < 0) {
			pb_name(&r, w, &t->child, &t->child_len);
		} else if (f == 3) {
			struct dao_rigid spare = t->tr;
			int rot = 0, first = list == 0 || (*n)++ == 0;
			pb_pose(&r, w, first ? &t->tr : &spare, first ? &rotation : &rot);
		} else if (f == 4 && list < 0) {
			pb_vector(&r, w, t->tr.t, 3);
		} else if (f == 5 && list < 0) {
			pb_rotation(&r, w, t->tr.q, &rotation);
		} else {
			dao_pb_skip(&r, w);
		}
	}
	return r.bad ? -EINVAL : 0;
}

/* One foxglove.FrameTransform of len bytes into t (its rotation the identity when left out). */
static int pb_frame_transform(const uint8_t *msg, size_t len, struct dao_tf_msg_transform *t)
{
	uint32_t n;
	return pb_framed(-1, msg, len, t, &n);
}

static int pb_frame_transforms(int list, const uint8_t *msg, size_t len, dao_tf_msg_cb cb,
			       void *user)
{
	struct dao_tf_msg_transform t;
	int r;
	if (!list) {
		if ((r = pb_frame_transform(msg, len, &t)) < 0)
			return r;
		return (r = cb(user, &t)) < 0 ? r : 0;
	}
	for (int pass = 0; pass < 2; pass++) { /* check all, then deliver */
		struct dao_pb m;
		uint32_t f, w;
		dao_pb_init(&m, msg, len);
		while (dao_pb_next(&m, &f, &w)) {
			size_t n;
			const uint8_t *p;
			if (f != 1) {
				dao_pb_skip(&m, w);
				continue;
			}
			if (w != DAO_PB_LEN || !(p = dao_pb_bytes(&m, &n)) ||
			    pb_frame_transform(p, n, &t) < 0)
				return -EINVAL;
			if (pass && (r = cb(user, &t)) < 0)
				return r;
		}
		if (m.bad)
			return -EINVAL;
	}
	return 0;
}

static int pb_calibration(const uint8_t *msg, size_t len, struct dao_fg_calibration *c)
{
	struct dao_pb r;
	uint32_t f, w, nk = 0, nr = 0, np = 0;
	char text[256];
	dao_pb_init(&r, msg, len);
	while (dao_pb_next(&r, &f, &w)) {
		switch (f) {
		case 1: c->stamp_ns = pb_timestamp(&r, w); break;
		case 2: c->width = pb_u32(&r, w); break;
		case 3: c->height = pb_u32(&r, w); break;
		case 4: pb_string(&r, w, text, sizeof text); break; /* distortion_model */
		case 5: pb_doubles(&r, w, c->d, DAO_FG_MAX_DISTORTION, &c->d_count); break;
		case 6: pb_doubles(&r, w, c->k, 9, &nk); break;
		case 7: pb_doubles(&r, w, c->r, 9, &nr); break;
		case 8: pb_doubles(&r, w, c->p, 12, &np); break;
		case 9: pb_string(&r, w, text, sizeof text); break; /* frame_id */
		default: dao_pb_skip(&r, w);
		}
	}
	return r.bad || nk != 9 || (nr != 0 && nr != 9) || (np != 0 && np != 12) ? -EINVAL : 0;
}

/* ---- JSON ---- */

static int8_t b64_value(unsigned char c)
{
	if (c >= 'A' && c <= 'Z')
		return (int8_t)(c - 'A');
	if (c >= 'a' && c <= 'z')
		return (int8_t)(c - 'a' + 26);
	if (c >= '0' && c <= '9')
		return (int8_t)(c - '0' + 52);
	return c == '+' ? 62 : c == '/' ? 63 : -1;
}

long dao_base64_decode(const char *in, size_t len, uint8_t *out, size_t cap)
{
	while (len > 0 && in[len - 1] == '=')
		len--;
	if (len % 4 == 1 || len / 4 * 3 + (len % 4 ? len % 4 - 1 : 0) > cap || len > LONG_MAX)
		return -1;
	size_t o = 0;
	uint32_t acc = 0;
	for (size_t i = 0; i < len; i++) {
		int8_t v = b64_value((unsigned char)in[i]);
		if (v < 0)
			return -1;
		acc = acc << 6 | (uint32_t)v;
		if (i % 4 == 3) {
			out[o++] = (uint8_t)(acc >> 16);
			out[o++] = (uint8_t)(acc >> 8);
			out[o++] = (uint8_t)acc;
			acc = 0;
		}
	}
	if (len % 4 == 2) {
		out[o++] = (uint8_t)(acc >> 4);
	} else if (len % 4 == 3) {
		out[o++] = (uint8_t)(acc >> 10);
		out[o++] = (uint8_t)(acc >> 2);
	}
	return (long)o;
}

void dao_fg_buf_free(struct dao_fg_buf *b)
{
	free(b->p);
	b->p = NULL;
	b->cap = 0;
}

static struct json_object *json_parse(const uint8_t *msg, size_t len)
{
	if (len > INT32_MAX)
		return NULL;
	struct json_tokener *tok = json_tokener_new_ex(16);
	if (!tok)
		return NULL;
	struct json_object *o = json_tokener_parse_ex(tok, (const char *)msg, (int)len);
	if (json_tokener_get_error(tok) != json_tokener_success || !json_object_is_type(o, json_type_object) ||
	    (size_t)json_tokener_get_parse_end(tok) != len) {
		json_object_put(o);
		o = NULL;
	}
	json_tokener_free(tok);
	return o;
}

/* A field: NULL if absent; *bad if present with another type. */
static struct json_object *jfield(struct json_object *o, const char *name, enum json_type t,
				  int *bad)
{
	struct json_object *v;
	if (!json_object_object_get_ex(o, name, &v) || !v)
		return NULL;
	if (!json_object_is_type(v, t)) {
		*bad = 1;
		return NULL;
	}
	return v;
}

static int64_t jint(struct json_object *o, const char *name, int64_t lo, int64_t hi, int *bad)
{
	struct json_object *v = jfield(o, name, json_type_int, bad);
	int64_t x = v ? json_object_get_int64(v) : 0;
	if (x < lo || x > hi)
		*bad = 1;
	return x < lo || x > hi ? 0 : x;
}

static uint64_t jstamp(struct json_object *o, int *bad)
{
	struct json_object *t = jfield(o, "timestamp", json_type_object, bad);
	if (!t)
		return 0;
	int64_t sec = jint(t, "sec", INT32_MIN, MAX_SECONDS, bad);
	int64_t nsec = jint(t, "nsec", 0, 999999999, bad);
	return stamp_ns(sec, nsec, bad);
}

static void jstring(struct json_object *o, const char *name, char *dst, size_t cap, int *bad)
{
	struct json_object *v = jfield(o, name, json_type_string, bad);
	const char *s = v ? json_object_get_string(v) : "";
	size_t n = v ? (size_t)json_object_get_string_len(v) : 0;
	if (n >= cap || strlen(s) != n) {
		*bad = 1;
		return;
	}
	memcpy(dst, s, n + 1);
}

/* The base64 field `name` decoded into buf (grown up to its max). */
static int jbytes(struct json_object *o, const char *name, struct dao_fg_buf *buf,
		  struct dao_fg_image *img, int *bad)
{
	struct json_object *v = jfield(o, name, json_type_string, bad);
	if (!v)
		return 0;
	size_t n = (size_t)json_object_get_string_len(v);
	size_t need = n / 4 * 3 + 3;
	if (need > buf->max)
		return -EFBIG;
	if (need > buf->cap) {
		uint8_t *p = realloc(buf->p, need);
		if (!p)
			return -ENOMEM;
		buf->p = p;
		buf->cap = need;
	}
	long got = dao_base64_decode(json_object_get_string(v), n, buf->p, buf->cap);
	if (got < 0)
		*bad = 1;
	img->data = buf->p;
	img->data_len = got < 0 ? 0 : (size_t)got;
	return 0;
}

static int json_image(const uint8_t *msg, size_t len, int raw, struct dao_fg_buf *buf,
		      struct dao_fg_image *img)
{
	struct json_object *o = json_parse(msg, len);
	int bad = 0, r;
	if (!o)
		return -EINVAL;
	img->stamp_ns = jstamp(o, &bad);
	if (raw) {
		img->width = (uint32_t)jint(o, "width", 0, UINT32_MAX, &bad);
		img->height = (uint32_t)jint(o, "height", 0, UINT32_MAX, &bad);
		img->step = (uint32_t)jint(o, "step", 0, UINT32_MAX, &bad);
	}
	jstring(o, raw ? "encoding" : "format", img->encoding, sizeof img->encoding, &bad);
	jstring(o, "frame_id", img->frame_id, sizeof img->frame_id, &bad);
	r = jbytes(o, "data", buf, img, &bad);
	json_object_put(o);
	return r < 0 ? r : bad ? -EINVAL : 0;
}

static void jdoubles(struct json_object *o, const char *name, double *dst, uint32_t cap,
		     uint32_t *count, int *bad)
{
	struct json_object *a = jfield(o, name, json_type_array, bad);
	size_t n = a ? json_object_array_length(a) : 0;
	*count = n > UINT32_MAX ? UINT32_MAX : (uint32_t)n;
	for (size_t i = 0; i < n; i++) {
		struct json_object *v = json_object_array_get_idx(a, i);
		if (!json_object_is_type(v, json_type_double) && !json_object_is_type(v, json_type_int)) {
			*bad = 1;
			return;
		}
		if (i < cap)
			dst[i] = json_object_get_double(v);
	}
}

static int json_calibration(const uint8_t *msg, size_t len, struct dao_fg_calibration *c)
{
	struct json_object *o = json_parse(msg, len);
	int bad = 0;
	uint32_t nk, nr, np;
	if (!o)
		return -EINVAL;
	c->stamp_ns = jstamp(o, &bad);
	c->width = (uint32_t)jint(o, "width", 0, UINT32_MAX, &bad);
	c->height = (uint32_t)jint(o, "height", 0, UINT32_MAX, &bad);
	jdoubles(o, "D", c->d, DAO_FG_MAX_DISTORTION, &c->d_count, &bad);
	jdoubles(o, "K", c->k, 9, &nk, &bad);
	jdoubles(o, "R", c->r, 9, &nr, &bad);
	jdoubles(o, "P", c->p, 12, &np, &bad);
	json_object_put(o);
	return bad || nk != 9 || (nr != 0 && nr != 9) || (np != 0 && np != 12) ? -EINVAL : 0;
}

/* A number field into *out (left as it is when absent or null). */
static void jnumber(struct json_object *o, const char *name, double *out, int *bad)
{
	struct json_object *v;
	if (!json_object_object_get_ex(o, name, &v) || !v)
		return;
	if (json_object_is_type(v, json_type_double) || json_object_is_type(v, json_type_int))
		*out = json_object_get_double(v);
	else
		*bad = 1;
}

/* A string field's bytes (in o), or "" when absent. */
static void jname(struct json_object *o, const char *name, const char **s, uint32_t *len,
		  int *bad)
{
	struct json_object *v = jfield(o, name, json_type_string, bad);
	*s = v ? json_object_get_string(v) : "";
	*len = v ? (uint32_t)json_object_get_string_len(v) : 0;
}

/* o's Vector3 `tn` and Quaternion `rn` into tr (as protobuf: a rotation left out is the
 * identity, a component left out 0). */
static void jrigid(struct json_object *o, const char *tn, const char *rn, struct dao_rigid *tr,
		   int *bad)
{
	static const char *const xyzw[] = { "x", "y", "z", "w" };
	struct json_object *v = jfield(o, tn, json_type_object, bad);
	for (int i = 0; v && i < 3; i++)
		jnumber(v, xyzw[i], &tr->t[i], bad);
	if ((v = jfield(o, rn, json_type_object, bad)) != NULL)
		tr->q[3] = 0.0;
	for (int i = 0; v && i < 4; i++)
		jnumber(v, xyzw[i], &tr->q[i], bad);
}

static int json_frame_transform(struct json_object *o, struct dao_tf_msg_transform *t)
{
	int bad = 0;
	frame_transform_init(t);
	if (!json_object_is_type(o, json_type_object))
		return -EINVAL;
	t->stamp_ns = jstamp(o, &bad);
	jname(o, "parent_frame_id", &t->parent, &t->parent_len, &bad);
	jname(o, "child_frame_id", &t->child, &t->child_len, &bad);
	jrigid(o, "translation", "rotation", &t->tr, &bad);
	return bad ? -EINVAL : 0;
}

static int json_frame_transforms(int list, const uint8_t *msg, size_t len, dao_tf_msg_cb cb,
				 void *user)
{
	struct json_object *o = json_parse(msg, len);
	struct dao_tf_msg_transform t;
	int bad = 0, r = 0;
	if (!o)
		return -EINVAL;
	struct json_object *a = list ? jfield(o, "transforms", json_type_array, &bad) : NULL;
	size_t n = !list ? 1 : a ? json_object_array_length(a) : 0;
	for (int pass = 0; pass < 2 && !bad && r == 0; pass++) /* check all, then deliver */
		for (size_t i = 0; i < n && !bad && r == 0; i++) {
			if (json_frame_transform(list ? json_object_array_get_idx(a, i) : o, &t) < 0)
				bad = 1;
			else if (pass)
				r = cb(user, &t);
		}
	json_object_put(o);
	return bad ? -EINVAL : r < 0 ? r : 0;
}

/* foxglove.PoseInFrame (list 0: "pose") or PosesInFrame (list 1: "poses", one only). */
static int json_poses(int list, const uint8_t *msg, size_t len, dao_tf_msg_cb cb, void *user)
{
	struct json_object *o = json_parse(msg, len);
	struct dao_tf_msg_transform t;
	int bad = 0, r;
	if (!o)
		return -EINVAL;
	frame_transform_init(&t);
	t.stamp_ns = jstamp(o, &bad);
	jname(o, "frame_id", &t.parent, &t.parent_len, &bad);
	struct json_object *a = list ? jfield(o, "poses", json_type_array, &bad) : NULL;
	size_t n = !list ? 1 : a ? json_object_array_length(a) : 0;
	struct json_object *pose = !list ? jfield(o, "pose", json_type_object, &bad)
				   : n ? json_object_array_get_idx(a, 0) : NULL;
	if (list && n && !json_object_is_type(pose, json_type_object))
		bad = 1;
	else if (pose)
		jrigid(pose, "position", "orientation", &t.tr, &bad);
	r = bad ? -EINVAL : n != 1 ? -ERANGE : cb(user, &t);
	json_object_put(o);
	return r < 0 ? r : 0;
}

int dao_fg_poses_parse(enum dao_fg_encoding enc, int list, const uint8_t *msg, size_t len,
		       dao_tf_msg_cb cb, void *user)
{
	struct dao_tf_msg_transform t;
	uint32_t n;
	int r;
	if (enc == DAO_FG_CDR)
		return dao_ros2_fg_pose_parse(list, msg, len, cb, user);
	if (enc == DAO_FG_JSON)
		return json_poses(list, msg, len, cb, user);
	if ((r = pb_framed(list, msg, len, &t, &n)) < 0)
		return r;
	if (n != 1)
		return -ERANGE;
	return (r = cb(user, &t)) < 0 ? r : 0;
}

int dao_fg_frame_transforms_parse(enum dao_fg_encoding enc, int list, const uint8_t *msg,
				  size_t len, dao_tf_msg_cb cb, void *user)
{
	if (enc == DAO_FG_CDR)
		return list ? dao_ros2_tf_parse(msg, len, cb, user)
			    : dao_ros2_fg_transform_parse(msg, len, cb, user);
	return enc == DAO_FG_JSON ? json_frame_transforms(list, msg, len, cb, user)
				  : pb_frame_transforms(list, msg, len, cb, user);
}

int dao_fg_raw_image_parse(enum dao_fg_encoding enc, const uint8_t *msg, size_t len,
			   struct dao_fg_buf *buf, struct dao_fg_image *img)
{
	memset(img, 0, sizeof(*img));
	if (enc == DAO_FG_CDR)
		return dao_ros2_fg_image_parse(0, msg, len, img);
	return enc == DAO_FG_JSON ? json_image(msg, len, 1, buf, img) : pb_raw_image(msg, len, img);
}

int dao_fg_compressed_image_parse(enum dao_fg_encoding enc, const uint8_t *msg, size_t len,
				  struct dao_fg_buf *buf, struct dao_fg_image *img)
{
	memset(img, 0, sizeof(*img));
	if (enc == DAO_FG_CDR)
		return dao_ros2_fg_image_parse(1, msg, len, img);
	return enc == DAO_FG_JSON ? json_image(msg, len, 0, buf, img)
				  : pb_compressed_image(msg, len, img);
}

int dao_fg_calibration_parse(enum dao_fg_encoding enc, const uint8_t *msg, size_t len,
			     struct dao_fg_calibration *cal)
{
	memset(cal, 0, sizeof(*cal));
	if (enc == DAO_FG_CDR)
		return dao_ros2_fg_calibration_parse(msg, len, cal);
	return enc == DAO_FG_JSON ? json_calibration(msg, len, cal) : pb_calibration(msg, len, cal);
}
