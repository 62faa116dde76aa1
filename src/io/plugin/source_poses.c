/* SPDX-License-Identifier: MIT */
/* A recording's camera poses from its tf, Foxglove transforms or poses, odometry or IMU
 * (source_poses.h). */
#include "plugin/source_poses.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "tf/imu_track.h"
#include "tf/tf_buffer.h"

struct dao_source_poses {
	char frame[256], topic[256];
	uint64_t gap_ns;
	int loaded;                 /* 0 not yet, 1 loaded, < 0 failed for good (failure) */
	struct dao_error failure;
	struct dao_tf_buffer *tf;
	char topics[120];           /* the topics read, for messages */
	uint64_t skipped;           /* transforms and messages refused */
	char skip_reason[200];      /* the first one's */
	char odom_child[256];       /* odometry: the first message's child_frame_id (a pose */
				    /* topic's: "pose of TOPIC", the camera's frame) */
	char odom_frame[256];       /* ... and its header.frame_id (the default fixed frame) */
	int camera_pose;            /* a pose topic gives the camera's pose */
	int imu;                    /* the pose topic is an IMU: 1 its rates, 2 its orientation */
	struct dao_tf_buffer *imu_tf; /* its rotation: imu_fixed -> imu_frame */
	char imu_fixed[256];        /* "rotation of TOPIC" */
	char imu_frame[256];        /* the first message's frame_id (no leading '/'), or "" */
	int imu_fixed_i, imu_frame_i; /* their frames in imu_tf */
	int imu_mount;              /* the depth frame's pose in the IMU's frame from the tf */
	uint64_t *imu_breaks;       /* the first stamps after the gaps (the rotation restarts) */
	size_t imu_nbreaks;
	long imu_segment;           /* the segment (between gaps) of the last frame's pose, -1:
				     * it had none (or a seek back: nothing to continue) */
	uint64_t imu_stamp;         /* the last frame's stamp ... */
	int imu_refused;            /* ... refused for a gap: asked again, refused again */
	long imu_segment_before;    /* imu_segment before the last frame (for a repeat) */
	char depth_frame[256];      /* the frame resolved for (the depth images' frame_id) */
	int resolved, source, target;
	char description[160];
	char warning[256];
	int warned;
};

/* What one message's transforms are added with. */
struct loading {
	struct dao_source_poses *p;
	const char *topic;
	uint32_t index;
	enum dao_pose_topic kind;
	struct dao_error *err;
	char pose_child[256];       /* a pose topic's frame: "pose of TOPIC" */
};

int dao_source_poses_create(struct dao_source_poses **out, const struct dao_ros_uri *u,
			    struct dao_error *err)
{
	struct dao_source_poses *p = calloc(1, sizeof(*p));
	if (!p)
		return dao_error_set(err, -ENOMEM, "out of memory");
	snprintf(p->frame, sizeof p->frame, "%s", u->pose_frame);
	snprintf(p->topic, sizeof p->topic, "%s", u->pose_topic);
	p->gap_ns = (uint64_t)(u->pose_gap * 1e9 + 0.5);
	*out = p;
	return 0;
}

void dao_source_poses_free(struct dao_source_poses *p)
{
	if (!p)
		return;
	dao_tf_buffer_free(p->tf);
	dao_tf_buffer_free(p->imu_tf);
	free(p->imu_breaks);
	free(p);
}

static void skip(struct dao_source_poses *p, const char *topic, uint32_t i, const char *why)
{
	if (p->skipped++ == 0)
		snprintf(p->skip_reason, sizeof p->skip_reason, "message %u of '%.50s': %.120s", i, topic,
			 why);
}

static int add(void *user, const struct dao_tf_msg_transform *t)
{
	struct loading *l = user;
	struct dao_error e;
	/* Foxglove has no /tf_static: a transform stamped 0 holds at every time, and so does
	 * a child frame's only transform (as Foxglove's 3D panel applies it) */
	int time = l->kind == DAO_POSE_TOPIC_TF_STATIC ? DAO_TF_STATIC
		   : l->kind != DAO_POSE_TOPIC_FOXGLOVE ? DAO_TF_DYNAMIC
		   : t->stamp_ns == 0                   ? DAO_TF_STATIC
							: DAO_TF_STATIC_IF_ALONE;
	int r = dao_tf_buffer_add(l->p->tf, t->parent, t->parent_len, t->child, t->child_len,
				  t->stamp_ns, &t->tr, time, &e);
	if (r == 1)
		skip(l->p, l->topic, l->index, e.message);
	if (r < 0)
		*l->err = e;
	return r < 0 ? r : 0;
}

/* s after buf's text, as much as fits */
static void list_append(char *buf, size_t cap, const char *s)
{
	size_t n = strlen(buf), k = strlen(s);
	if (n + 1 >= cap)
		return;
	k = k < cap - 1 - n ? k : cap - 1 - n;
	memcpy(buf + n, s, k);
	buf[n + k] = 0;
}

static void list_add(char *buf, size_t cap, const char *name)
{
	size_t n = strlen(buf);
	if (n + 4 < cap)
		snprintf(buf + n, cap - n, "%s%s", n ? ", " : "", name);
}

/* An odometry or pose message's transform: its frames kept (the first message's), then
 * added; a pose's child is the camera's frame, "pose of TOPIC". */
static int add_pose(void *user, const struct dao_tf_msg_transform *t)
{
	struct loading *l = user;
	struct dao_source_poses *p = l->p;
	struct dao_tf_msg_transform c = *t;
	if (l->kind == DAO_POSE_TOPIC_POSE) {
		c.child = l->pose_child;
		c.child_len = (uint32_t)strlen(l->pose_child);
	}
	if (!p->odom_child[0] && c.child_len < sizeof p->odom_child &&
	    c.parent_len < sizeof p->odom_frame) {
		memcpy(p->odom_child, c.child, c.child_len);
		memcpy(p->odom_frame, c.parent, c.parent_len);
		p->camera_pose = l->kind == DAO_POSE_TOPIC_POSE;
	}
	return add(l, &c);
}

/* A PosesInFrame message of other than one pose: refused (which is the camera's?). */
static int not_one_pose(const struct dao_pose_feed *feed, const struct dao_pose_topic_info *ti,
			uint32_t i, struct dao_error *err)
{
	return dao_error_set(err, -ERANGE, "%s: message %u of '%s' (%s) has not exactly one pose: "
			     "which is the camera's is unknown; record it alone, or name another "
			     "pose_topic", feed->path, i, ti->name, ti->type);
}

/* Whether an IMU message has an orientation to take: marked as there (not
 * orientation_covariance[0] -1) and a unit quaternion within 1e-3, as a transform's (a
 * driver that fills none but the mark, with zeros, has none). */
static int imu_has_orientation(const struct dao_imu_msg *m)
{
	struct dao_rigid r = { .q = { m->q[0], m->q[1], m->q[2], m->q[3] } };
	const char *why;
	return m->has_orientation && dao_rigid_check(&r, 1e-3, &why) == 0;
}

/* A gyro's range is tens of rad/s; NaN fails too. */
static int imu_rates_usable(const struct dao_imu_msg *m)
{
	return fabs(m->w[0]) < 1e4 && fabs(m->w[1]) < 1e4 && fabs(m->w[2]) < 1e4;
}

/* An IMU message's frame_id as the tf names it (no leading '/'), *n 0 where it names no
 * frame: empty, "/", longer than a frame name or holding a NUL. */
static const char *imu_frame_name(const struct dao_imu_msg *m, uint32_t *n)
{
	const char *f = m->frame;
	*n = m->frame_len;
	if (*n && f[0] == '/')
		f++, (*n)--;
	if (*n > DAO_TF_NAME_MAX || memchr(f, 0, *n))
		*n = 0;
	return f;
}

/* The first IMU message's frame_id kept ("" where it names none). */
static void imu_keep_frame(struct dao_source_poses *p, const struct dao_imu_msg *m)
{
	uint32_t n;
	const char *f = imu_frame_name(m, &n);
	memcpy(p->imu_frame, f, n);
	p->imu_frame[n] = 0;
}

/* Whether message m names the first message's frame (or, like it, none). */
static int imu_same_frame(const struct dao_source_poses *p, const struct dao_imu_msg *m)
{
	uint32_t n;
	const char *f = imu_frame_name(m, &n);
	return n == strlen(p->imu_frame) && !memcmp(f, p->imu_frame, n);
}

/* The usable messages of IMU topic t into v (at most ti->count), *n of them; *mode 2 for
 * orientations (the first message has one), else 1 (its rates). */
static int imu_collect(struct dao_source_poses *p, const struct dao_pose_feed *feed, uint32_t t,
		       const struct dao_pose_topic_info *ti, const char *why,
		       struct dao_imu_sample *v, size_t *n, int *mode, struct dao_error *err)
{
	*n = 0;
	*mode = 0;
	for (uint32_t i = 0; i < ti->count; i++) {
		const uint8_t *d;
		uint64_t len;
		struct dao_imu_msg m;
		int r = feed->read(feed->impl, t, i, &d, &len, err);
		if (r < 0)
			return r;
		if (feed->parse_imu(feed->impl, t, d, len, &m) < 0) {
			skip(p, ti->name, i, why);
			continue;
		}
		if (!*mode) {
			imu_keep_frame(p, &m);
			*mode = imu_has_orientation(&m) ? 2 : 1;
		}
		const char *bad = !imu_same_frame(p, &m) ? "another frame_id than the first message's"
				  : *mode == 2 && !imu_has_orientation(&m)
					  ? "no unit orientation, which the first message has"
				  : *mode == 1 && !imu_rates_usable(&m)
					  ? "an angular velocity not finite or beyond 1e4 rad/s"
					  : NULL;
		if (bad) {
			skip(p, ti->name, i, bad);
			continue;
		}
		v[*n].stamp_ns = m.stamp_ns;
		memcpy(v[*n].q, m.q, sizeof m.q);
		memcpy(v[*n].w, m.w, sizeof m.w);
		(*n)++;
	}
	return 0;
}

/* The track of the n samples of v (imu_track.h) into imu_tf, imu_fixed -> the IMU's frame
 * ("imu of TOPIC" where the messages name none), and the gaps' stamps into imu_breaks. */
static int imu_store(struct dao_source_poses *p, const char *path, const char *topic,
		     struct dao_imu_sample *v, size_t n, int mode, struct dao_error *err)
{
	n = dao_imu_track(v, n, mode == 2, p->gap_ns);
	size_t breaks = 0;
	for (size_t i = 1; i < n; i++)
		breaks += v[i].segment != v[i - 1].segment;
	if (breaks && !(p->imu_breaks = malloc(breaks * sizeof(*p->imu_breaks))))
		return dao_error_set(err, -ENOMEM, "out of memory");
	for (size_t i = 1; i < n; i++)
		if (v[i].segment != v[i - 1].segment)
			p->imu_breaks[p->imu_nbreaks++] = v[i].stamp_ns;
	int r = dao_tf_buffer_create(&p->imu_tf, 2, DAO_POSES_MAX_SAMPLES, err);
	if (r < 0)
		return r;
	char child[300];
	snprintf(p->imu_fixed, sizeof p->imu_fixed, "rotation of %.200s", topic);
	snprintf(child, sizeof child, "%s%.200s", p->imu_frame[0] ? "" : "imu of ",
		 p->imu_frame[0] ? p->imu_frame : topic);
	for (size_t i = 0; i < n; i++) {
		struct dao_rigid tr = { .q = { v[i].q[0], v[i].q[1], v[i].q[2], v[i].q[3] } };
		struct dao_error e;
		r = dao_tf_buffer_add(p->imu_tf, p->imu_fixed, strlen(p->imu_fixed), child,
				      strlen(child), v[i].stamp_ns, &tr, DAO_TF_DYNAMIC, &e);
		if (r < 0)
			return *err = e, r;
		if (r) /* refused: the names (an IMU frame named as imu_fixed is its own parent) */
			return dao_error_set(err, -EINVAL, "%s: the IMU topic '%s': %s; rename its "
					     "frame_id", path, topic, e.message);
	}
	if ((r = dao_tf_buffer_finish(p->imu_tf, err)) < 0)
		return r;
	p->imu_fixed_i = dao_tf_buffer_find(p->imu_tf, p->imu_fixed);
	p->imu_frame_i = dao_tf_buffer_find(p->imu_tf, child);
	p->imu = mode;
	p->imu_segment = p->imu_segment_before = -1;
	p->imu_refused = 0;
	return 0;
}

/*
 * An IMU topic: its rotation (imu_track.h) as the transforms from its frame (the first
 * message's frame_id) to "rotation of TOPIC", stamped as the messages, no translation.
 * The first message decides: its orientation where it has one (messages without are
 * skipped), else the angular velocity of every message, integrated.
 */
static int read_imu(struct dao_source_poses *p, const struct dao_pose_feed *feed, uint32_t t,
		    const struct dao_pose_topic_info *ti, const char *why, struct dao_error *err)
{
	if (ti->count > DAO_POSES_MAX_SAMPLES)
		return dao_error_set(err, -E2BIG, "%s: '%s' has %u messages, more than the %u "
				     "read for poses (35 minutes at 1 kHz); cut the recording",
				     feed->path, ti->name, ti->count, DAO_POSES_MAX_SAMPLES);
	struct dao_imu_sample *v = ti->count ? malloc(ti->count * sizeof(*v)) : NULL;
	if (ti->count && !v)
		return dao_error_set(err, -ENOMEM, "out of memory");
	size_t n;
	int mode, r = imu_collect(p, feed, t, ti, why, v, &n, &mode, err);
	if (r >= 0 && !n)
		r = dao_error_set(err, -ENODATA, "%s: the IMU topic '%s' has no message that can be "
				  "read%s%s", feed->path, ti->name, p->skipped ? ": " : "",
				  p->skipped ? p->skip_reason : "");
	if (r >= 0)
		r = imu_store(p, feed->path, ti->name, v, n, mode, err);
	free(v);
	return r < 0 ? r : 0;
}

/* Every message of topic t into the buffer. */
static int read_topic(struct dao_source_poses *p, const struct dao_pose_feed *feed, uint32_t t,
		      struct dao_error *err)
{
	struct dao_pose_topic_info ti;
	feed->topic(feed->impl, t, &ti);
	const char *name = ti.name;
	const enum dao_pose_topic kind = ti.kind;
	char why[120];
	snprintf(why, sizeof why, "not a %.60s%s%.20s%s", ti.type, ti.encoding[0] ? " (" : "",
		 ti.encoding, ti.encoding[0] ? ")" : "");
	list_add(p->topics, sizeof p->topics, name);
	struct loading l = { p, name, 0, kind, err, "" };
	snprintf(l.pose_child, sizeof l.pose_child, "pose of %s", name);
	if (kind == DAO_POSE_TOPIC_IMU)
		return read_imu(p, feed, t, &ti, why, err);
	for (uint32_t i = 0; i < ti.count; i++) {
		const uint8_t *d;
		uint64_t len;
		int r = feed->read(feed->impl, t, i, &d, &len, err);
		if (r < 0)
			return r;
		l.index = i;
		if (kind == DAO_POSE_TOPIC_ODOMETRY || kind == DAO_POSE_TOPIC_POSE)
			r = feed->parse_pose(feed->impl, t, d, len, add_pose, &l);
		else
			r = feed->parse_tf(feed->impl, t, d, len, add, &l);
		if (r == -ERANGE)
			return not_one_pose(feed, &ti, i, err);
		if (r == -EINVAL || r == -ENOTSUP)
			skip(p, name, i, why);
		else if (r < 0)
			return r;
	}
	return 0;
}

static int is_transforms(enum dao_pose_topic kind)
{
	return kind == DAO_POSE_TOPIC_TF || kind == DAO_POSE_TOPIC_TF_STATIC ||
	       kind == DAO_POSE_TOPIC_FOXGLOVE;
}

/* A Foxglove transform or pose topic in an encoding not read. */
static int refused(const struct dao_pose_feed *feed, const struct dao_pose_topic_info *ti,
		   struct dao_error *err)
{
	return dao_error_set(err, -EINVAL, "%s: topic '%s' is %s in message encoding '%s' "
			     "(schema encoding '%s'); read are protobuf, json (jsonschema) and, for "
			     "foxglove_msgs/msg/*, cdr", feed->path, ti->name, ti->type, ti->encoding,
			     ti->schema_encoding);
}

/* A topic that gives the camera's pose (or rotation) alone: odometry, Foxglove poses, an
 * IMU. */
static int is_poses(enum dao_pose_topic kind)
{
	return kind == DAO_POSE_TOPIC_ODOMETRY || kind == DAO_POSE_TOPIC_POSE ||
	       kind == DAO_POSE_TOPIC_IMU;
}

/* The topic named by pose_topic (odometry, poses, an IMU or transforms): its index, or < 0
 * with the topics there are. */
static int pose_topic(struct dao_source_poses *p, const struct dao_pose_feed *feed,
		      struct dao_error *err)
{
	char odom[100] = "", tf[100] = "";
	for (uint32_t t = 0; t < feed->topic_count; t++) {
		struct dao_pose_topic_info ti;
		feed->topic(feed->impl, t, &ti);
		if (!strcmp(ti.name, p->topic) && (ti.kind == DAO_POSE_TOPIC_REFUSED ||
						   ti.kind == DAO_POSE_TOPIC_POSE_REFUSED))
			return refused(feed, &ti, err);
		if (!strcmp(ti.name, p->topic) && (is_poses(ti.kind) || is_transforms(ti.kind)))
			return (int)t;
		if (is_poses(ti.kind))
			list_add(odom, sizeof odom, ti.name);
		else if (is_transforms(ti.kind))
			list_add(tf, sizeof tf, ti.name);
	}
	return dao_error_set(err, -EINVAL, "%s: no nav_msgs/Odometry, Foxglove PoseInFrame(s) "
			     "or sensor_msgs/Imu topic '%s' (pose_topic), nor transforms; "
			     "odometry, pose and IMU topics: %s; transform topics: %s", feed->path,
			     p->topic, odom[0] ? odom : "none", tf[0] ? tf : "none");
}

/*
 * The topics read into a new buffer: every transform topic; or, with pose_topic, that
 * topic (odometry, poses, an IMU or transforms) and the static transform topics.
 */
static int load(struct dao_source_poses *p, const struct dao_pose_feed *feed,
		struct dao_error *err)
{
	int sel = -1, ndynamic = 0, r;
	if (p->topic[0] && (sel = pose_topic(p, feed, err)) < 0)
		return sel;
	if ((r = dao_tf_buffer_create(&p->tf, DAO_POSES_MAX_FRAMES, DAO_POSES_MAX_SAMPLES, err)) < 0)
		return r;
	for (uint32_t t = 0; t < feed->topic_count; t++) { /* the odometry first */
		struct dao_pose_topic_info ti;
		feed->topic(feed->impl, t, &ti);
		if (ti.kind == DAO_POSE_TOPIC_REFUSED && (sel < 0 || ti.static_name))
			return refused(feed, &ti, err);
		if ((int)t == sel && is_poses(ti.kind) &&
		    (r = read_topic(p, feed, t, err)) < 0)
			return r;
	}
	for (uint32_t t = 0; t < feed->topic_count; t++) {
		struct dao_pose_topic_info ti;
		feed->topic(feed->impl, t, &ti);
		if (!is_transforms(ti.kind) ||
		    (ti.kind != DAO_POSE_TOPIC_TF_STATIC && sel >= 0 && (int)t != sel))
			continue;
		ndynamic += ti.kind != DAO_POSE_TOPIC_TF_STATIC;
		if ((r = read_topic(p, feed, t, err)) < 0)
			return r;
	}
	if (sel < 0 && ndynamic == 0)
		return dao_error_set(err, -ENODATA, "%s: no tf topic (tf2_msgs/TFMessage, "
				     "foxglove.FrameTransform(s)) for the camera's poses%s%s; name a "
				     "nav_msgs/Odometry, PoseInFrame(s) or sensor_msgs/Imu topic "
				     "(pose_topic), or use motion icp or off",
				     feed->path, p->topics[0] ? ", only " : "", p->topics);
	char skipped[sizeof p->warning] = "";
	if (p->skipped)
		snprintf(skipped, sizeof skipped, "%llu transforms or messages of %.40s skipped as "
			 "malformed (the first: %.120s)", (unsigned long long)p->skipped, p->topics,
			 p->skip_reason);
	if (p->imu) /* the IMU's note first: the skipped part may not fit after it */
		snprintf(p->warning, sizeof p->warning, "%.40s is an IMU: a rotation (%s), no "
			 "translation; source+icp finds the translation%s", p->topic,
			 p->imu == 2 ? "its orientation" : "its rates integrated",
			 skipped[0] ? "; " : "");
	list_append(p->warning, sizeof p->warning, skipped);
	return dao_tf_buffer_finish(p->tf, err);
}

/* "", or what was skipped (a transform left out may be why a frame is missing). */
static const char *skipped_note(const struct dao_source_poses *p, char *buf, size_t cap)
{
	if (!p->skipped)
		return "";
	snprintf(buf, cap, " (%llu skipped as malformed, the first: %.100s)",
		 (unsigned long long)p->skipped, p->skip_reason);
	return buf;
}

/* Frame `name` of the buffer, or an error saying which frames there are. */
static int frame_of(struct dao_source_poses *p, const struct dao_pose_feed *feed,
		    const char *name, const char *what, struct dao_error *err)
{
	int f = dao_tf_buffer_find(p->tf, name);
	if (f >= 0)
		return f;
	char list[300], note[160];
	dao_tf_buffer_list(p->tf, list, sizeof list);
	return dao_error_set(err, -EINVAL, "%s: %s '%s' is not in %s%s; frames seen: %s",
			     feed->path, what, name, p->topics, skipped_note(p, note, sizeof note),
			     list[0] ? list : "none");
}

/* Odometry whose child the depth frame is not connected to: the child taken for the camera. */
static int odometry_fallback(struct dao_source_poses *p, const char *depth, struct dao_error *err)
{
	int c = dao_tf_buffer_find(p->tf, p->odom_child), r;
	if (c < 0 || (r = dao_tf_buffer_connected(p->tf, c, p->target, err)) <= 0)
		return -1;
	snprintf(p->warning, sizeof p->warning, "%.40s: no transform from the odometry's "
		 "'%.50s' to the depth frame '%.50s': the odometry's pose is taken as the "
		 "camera's", p->topics, p->odom_child, depth);
	p->warned = 0;
	return c;
}

/*
 * An IMU's poses for the depth images' frame `depth`: the IMU's rotation (imu_tf) after the
 * depth frame's pose in the IMU's frame (the tf's transforms between them, as at each
 * frame's time), or the IMU's axes taken for the optical frame's where no transform
 * connects them (or the messages name no frame).
 */
static int resolve_imu(struct dao_source_poses *p, const struct dao_pose_feed *feed,
		       const char *depth, struct dao_error *err)
{
	p->resolved = 0;
	if (p->frame[0])
		return dao_error_set(err, -EINVAL, "%s: pose_frame '%s' with the IMU topic '%s': an "
				     "IMU's rotation has no frame of the tf to be in (it is from where "
				     "it started); leave pose_frame out", feed->path, p->frame,
				     p->topic);
	const char *d = depth[0] == '/' ? depth + 1 : depth;
	const int s = dao_tf_buffer_find(p->tf, depth);
	const int i = p->imu_frame[0] ? dao_tf_buffer_find(p->tf, p->imu_frame) : -1;
	int r = s >= 0 && i >= 0 ? dao_tf_buffer_connected(p->tf, s, i, err) : 0;
	if (r < 0)
		return r;
	p->imu_mount = r && s != i;
	if (!r && strcmp(d, p->imu_frame)) {
		char note[sizeof p->warning];
		snprintf(note, sizeof note, "%s", p->warning);
		snprintf(p->warning, sizeof p->warning, "no transform from the IMU's '%.40s' to "
			 "'%.40s': its axes taken for the optical frame's; ",
			 p->imu_frame[0] ? p->imu_frame : "(no frame_id)", d);
		list_append(p->warning, sizeof p->warning, note);
		p->warned = 0;
	}
	p->source = s;
	p->target = i;
	p->resolved = 1;
	snprintf(p->depth_frame, sizeof p->depth_frame, "%s", depth);
	snprintf(p->description, sizeof p->description, "'%.50s' in '%.60s' (%llu samples)%s",
		 depth, p->imu_fixed, (unsigned long long)dao_tf_buffer_samples(p->imu_tf),
		 p->imu_mount ? ", mounted as the tf has it" : "");
	return 0;
}

/* The segment (between the IMU's gaps) stamp_ns falls in: how many gaps precede it. */
static long imu_segment_of(const struct dao_source_poses *p, uint64_t stamp_ns)
{
	size_t lo = 0, hi = p->imu_nbreaks;
	while (lo < hi) {
		const size_t mid = lo + (hi - lo) / 2;
		if (p->imu_breaks[mid] <= stamp_ns)
			lo = mid + 1;
		else
			hi = mid;
	}
	return (long)lo;
}

/* The pose of the depth frame at stamp_ns from the IMU (resolve_imu); -ENOENT for the first
 * frame after a gap whose frame before had a pose: the IMU's turn in the gap is unknown,
 * so the motion between the two poses would be wrong.  The answer for one frame is the
 * same however often it is asked; a seek back starts afresh. */
static int imu_pose(struct dao_source_poses *p, uint64_t stamp_ns, struct dao_rigid *out,
		    struct dao_error *err)
{
	if (p->imu_refused && stamp_ns == p->imu_stamp)
		goto gap;
	long last = p->imu_segment;
	if (stamp_ns < p->imu_stamp)
		last = -1; /* a seek back, or frames out of order: nothing to continue */
	else if (stamp_ns == p->imu_stamp)
		last = p->imu_segment_before;
	p->imu_segment_before = last;
	p->imu_stamp = stamp_ns;
	p->imu_segment = -1;
	p->imu_refused = 0;
	struct dao_rigid rot, mount;
	int r = dao_tf_buffer_lookup(p->imu_tf, p->imu_fixed_i, p->imu_frame_i, stamp_ns,
				     p->gap_ns, &rot, err);
	if (r < 0)
		return r;
	/* the segment of the sample the lookup may have snapped to (within its 1 us) */
	const long seg = imu_segment_of(p, stamp_ns + 1000);
	if (last >= 0 && seg != last) {
		p->imu_refused = 1;
		goto gap;
	}
	dao_rigid_identity(&mount);
	if (p->imu_mount &&
	    (r = dao_tf_buffer_lookup(p->tf, p->target, p->source, stamp_ns, p->gap_ns, &mount,
				      err)) < 0)
		return r;
	dao_rigid_compose(&rot, &mount, out);
	/* no translation: the IMU measures none (the rotation about the IMU's origin would
	 * move the camera by its lever arm, which is no better a guess than not at all) */
	out->t[0] = out->t[1] = out->t[2] = 0.0;
	p->imu_segment = seg;
	return 0;
gap:
	return dao_error_set(err, -ENOENT, "no pose at %.6f s: the IMU's messages have a gap "
			     "(more than pose_gap) since the last frame, and its turn in the gap "
			     "is unknown", (double)stamp_ns * 1e-9);
}

/* The source and target frames for the depth images' frame `depth`. */
static int resolve(struct dao_source_poses *p, const struct dao_pose_feed *feed,
		   const char *depth, struct dao_error *err)
{
	/* a pose topic's pose is the camera's: its frame stands for the depth frame */
	int s = dao_tf_buffer_find(p->tf, p->camera_pose ? p->odom_child : depth);
	/* the fixed frame: pose_frame, the odometry's frame, the root of the depth frame's tree */
	const char *fixed = p->frame[0] ? p->frame : p->odom_frame[0] ? p->odom_frame : depth;
	p->resolved = 0;
	p->target = frame_of(p, feed, fixed, p->frame[0] ? "the fixed frame (pose_frame)"
			     : !p->odom_frame[0] ? "the depth frame"
			     : p->camera_pose ? "the pose's frame_id" : "the odometry's frame", err);
	if (p->target < 0)
		return p->target;
	int r = fixed == depth ? dao_tf_buffer_root(p->tf, p->target, &p->target, err) : 0;
	if (r < 0)
		return r;
	r = s < 0 ? 0 : dao_tf_buffer_connected(p->tf, s, p->target, err);
	if (r < 0)
		return r;
	if (!r && p->odom_child[0] && !p->camera_pose)
		r = (s = odometry_fallback(p, depth, err)) >= 0;
	const char *tn = dao_tf_buffer_frame_name(p->tf, (uint32_t)p->target);
	if (!r) {
		char list[300], note[160];
		dao_tf_buffer_list(p->tf, list, sizeof list);
		return dao_error_set(err, -ENOTCONN, "%s: the depth frame '%s' is %s '%s' in %s%s; "
				     "frames seen: %s", feed->path, depth,
				     s < 0 ? "not in the tf, so not connected to" : "not connected to",
				     tn, p->topics, skipped_note(p, note, sizeof note), list);
	}
	p->source = s;
	p->resolved = 1;
	snprintf(p->depth_frame, sizeof p->depth_frame, "%s", depth);
	snprintf(p->description, sizeof p->description, "'%.50s' in '%.40s' from %.40s (%llu "
		 "transforms)", dao_tf_buffer_frame_name(p->tf, (uint32_t)s), tn, p->topics,
		 (unsigned long long)dao_tf_buffer_samples(p->tf));
	return 0;
}

int dao_source_poses_get(struct dao_source_poses *p, const struct dao_pose_feed *feed,
			 const char *frame_id, uint32_t len, uint64_t stamp_ns,
			 struct dao_source_pose *pose, struct dao_error *err)
{
	char depth[DAO_TF_NAME_MAX + 1];
	int r;
	if (p->loaded == 0 && (r = load(p, feed, &p->failure)) < 0)
		p->loaded = r;
	else if (p->loaded == 0)
		p->loaded = 1;
	if (p->loaded < 0) {
		*err = p->failure;
		return p->loaded;
	}
	if (len == 0 || len > DAO_TF_NAME_MAX || (len == 1 && frame_id[0] == '/'))
		return dao_error_set(err, -EINVAL, "%s: the depth image's frame_id is %s: "
				     "its frame in the tf is unknown", feed->path,
				     len > 1 ? "too long" : len ? "'/'" : "empty");
	memcpy(depth, frame_id, len);
	depth[len] = 0;
	if ((!p->resolved || strcmp(depth, p->depth_frame)) &&
	    (r = p->imu ? resolve_imu(p, feed, depth, err) : resolve(p, feed, depth, err)) < 0)
		return r;
	struct dao_rigid tr;
	if ((r = p->imu ? imu_pose(p, stamp_ns, &tr, err)
			: dao_tf_buffer_lookup(p->tf, p->target, p->source, stamp_ns, p->gap_ns, &tr,
					       err)) < 0)
		return r;
	memcpy(pose->rotation, tr.q, sizeof tr.q);
	memcpy(pose->translation, tr.t, sizeof tr.t);
	snprintf(pose->description, sizeof pose->description, "%s", p->description);
	pose->warning[0] = 0;
	if (!p->warned && p->warning[0])
		snprintf(pose->warning, sizeof pose->warning, "%s", p->warning);
	p->warned = 1;
	return 0;
}
