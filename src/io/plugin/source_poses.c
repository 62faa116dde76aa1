/* SPDX-License-Identifier: MIT */
/* A recording's camera poses from its tf, Foxglove transforms or poses, or odometry
 * (source_poses.h). */
#include "plugin/source_poses.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
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

/* A topic that gives the camera's pose alone: odometry or Foxglove poses. */
static int is_poses(enum dao_pose_topic kind)
{
	return kind == DAO_POSE_TOPIC_ODOMETRY || kind == DAO_POSE_TOPIC_POSE;
}

/* The topic named by pose_topic (odometry or transforms): its index, or < 0 with the topics
 * there are. */
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
	return dao_error_set(err, -EINVAL, "%s: no nav_msgs/Odometry or Foxglove PoseInFrame(s) "
			     "topic '%s' (pose_topic), nor transforms; odometry and pose topics: "
			     "%s; transform topics: %s", feed->path,
			     p->topic, odom[0] ? odom : "none", tf[0] ? tf : "none");
}

/*
 * The topics read into a new buffer: every transform topic; or, with pose_topic, that
 * topic (odometry or transforms) and the static transform topics.
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
				     "nav_msgs/Odometry or PoseInFrame(s) topic (pose_topic), or use "
				     "motion icp or off",
				     feed->path, p->topics[0] ? ", only " : "", p->topics);
	if (p->skipped)
		snprintf(p->warning, sizeof p->warning, "%llu transforms or messages of %.40s skipped "
			 "as malformed (the first: %.120s)", (unsigned long long)p->skipped, p->topics,
			 p->skip_reason);
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
	if (len == 0 || len > DAO_TF_NAME_MAX)
		return dao_error_set(err, -EINVAL, "%s: the depth image's frame_id is %s: "
				     "its frame in the tf is unknown", feed->path,
				     len ? "too long" : "empty");
	memcpy(depth, frame_id, len);
	depth[len] = 0;
	if ((!p->resolved || strcmp(depth, p->depth_frame)) && (r = resolve(p, feed, depth, err)) < 0)
		return r;
	struct dao_rigid tr;
	if ((r = dao_tf_buffer_lookup(p->tf, p->target, p->source, stamp_ns, p->gap_ns, &tr, err)) < 0)
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
