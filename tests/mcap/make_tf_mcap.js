// SPDX-License-Identifier: MIT
// Writes a plan of test_cli_tf_poses.py as MCAP (@mcap/core, zstd chunks) and as a rosbag2
// sqlite3 .db3 (sql.js), the messages in CDR by @foxglove/rosmsg2-serialization: the depth
// (sensor_msgs/msg/Image 16UC1) and its camera_info, /tf and /tf_static
// (tf2_msgs/msg/TFMessage), an odometry topic (nav_msgs/msg/Odometry) and an IMU topic
// (sensor_msgs/msg/Imu, as make_tf_bag.py writes it) when the plan has them.  With
// plan.fg_cdr, the transforms are Foxglove's ROS 2 messages instead, as
// make_fg_tf_mcap.js writes them (/tf foxglove_msgs/msg/FrameTransform, a message a transform,
// /tf_static FrameTransforms; plan.fg's static_topic, extra and encoding, and the transforms'
// fg), and plan.poses (make_fg_tf_mcap.js) as foxglove_msgs/msg/PoseInFrame(s); their .msg as
// @foxglove/schemas generates them.  PLAN_DIR/plan.json says what, PLAN_DIR/depth.raw holds the
// 16-bit frames.
// usage: node make_tf_mcap.js PLAN_DIR OUT.mcap OUT.db3  (exit 77 without tests/js/node_modules)
"use strict";
const fs = require("fs");
const path = require("path");

const M = require(path.join(__dirname, "make_mcaps.js"));
const D = require(path.join(__dirname, "..", "db3", "make_db3.js"));
const F = require(path.join(__dirname, "make_fg_tf_mcap.js"));
const initSqlJs = require(path.join(M.mods, "sql.js"));
const { generateRosMsgMergedSchema } = require(path.join(M.mods, "@foxglove/schemas/dist/internal/generateRos"));
const { foxgloveMessageSchemas } = require(path.join(M.mods, "@foxglove/schemas/dist/internal/schemas"));
const { SEP, HEADER, TIME, IMAGE, CAMINFO, writer } = M;

const VECTOR3 = "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n";
const QUATERNION = "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n";
const TF = "geometry_msgs/TransformStamped[] transforms\n" + SEP +
  "MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n" +
  "geometry_msgs/Transform transform\n" + SEP + HEADER + SEP + TIME + SEP +
  "MSG: geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\n" +
  "geometry_msgs/Quaternion rotation\n" + SEP + VECTOR3 + SEP + QUATERNION;
const ODOMETRY = "std_msgs/Header header\nstring child_frame_id\n" +
  "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n" + SEP +
  HEADER + SEP + TIME + SEP +
  "MSG: geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] covariance\n" + SEP +
  "MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n" +
  SEP + "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n" + SEP + QUATERNION + SEP +
  "MSG: geometry_msgs/TwistWithCovariance\ngeometry_msgs/Twist twist\nfloat64[36] covariance\n" +
  SEP + "MSG: geometry_msgs/Twist\ngeometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n" +
  SEP + VECTOR3;

const IMU = "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n" +
  "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n" +
  "float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n" +
  "float64[9] linear_acceleration_covariance\n" + SEP + HEADER + SEP + TIME + SEP + QUATERNION +
  SEP + VECTOR3;

const planDir = process.argv[2];
const plan = JSON.parse(fs.readFileSync(path.join(planDir, "plan.json"), "utf8"));
const raw = fs.readFileSync(path.join(planDir, "depth.raw"));
const W = plan.width, H = plan.height;

const stampOf = (ns) => ({ sec: Number(BigInt(ns) / 1000000000n), nanosec: Number(BigInt(ns) % 1000000000n) });
const header = (ns, frame) => ({ stamp: stampOf(ns), frame_id: frame });
const xyz = (v) => ({ x: v[0], y: v[1], z: v[2] });
const xyzw = (q) => ({ x: q[0], y: q[1], z: q[2], w: q[3] });
const transform = (t) => ({ header: header(t.stamp_ns, t.parent), child_frame_id: t.child,
  transform: { translation: xyz(t.t), rotation: xyzw(t.q) } });
const zeros = () => new Float64Array(36);

// Foxglove's ROS 2 messages: foxglove_msgs/msg/NAME in CDR, cut short where a value asks
function fgPut(put, topic, name, time, value, xs) {
  const def = generateRosMsgMergedSchema(foxgloveMessageSchemas[name], { rosVersion: 2 });
  put(topic, "foxglove_msgs/msg/" + name, def, time, value, (b) => F.damaged(b, xs));
}

function fgTransforms(put) {
  const fg = plan.fg || {};
  const one = (t) => F.frameTransform(t, "cdr");
  for (const g of plan.tf_static_messages)
    fgPut(put, fg.static_topic || "/tf_static", "FrameTransforms", plan.start_ns, { transforms: g.map(one) }, g);
  for (const g of plan.tf_messages)
    for (const t of g)
      fgPut(put, "/tf", "FrameTransform", t.stamp_ns, one(t), [t]);
  for (const x of fg.extra || [])
    fgPut(put, x.topic, "FrameTransforms", x.stamp_ns, { transforms: x.transforms.map(one) }, x.transforms);
}

// every message of the recording: { topic, type, def, time (ns, BigInt), bytes }
function messages() {
  const out = [];
  const put = (topic, type, def, time, value, cut = (b) => b) =>
    out.push({ topic, type, def, time: BigInt(time), bytes: cut(writer(def).writeMessage(value)) });
  if (plan.fg_cdr)
    fgTransforms(put);
  for (const g of plan.fg_cdr ? [] : plan.tf_static_messages)
    put("/tf_static", "tf2_msgs/msg/TFMessage", TF, plan.start_ns, { transforms: g.map(transform) });
  for (const g of plan.fg_cdr ? [] : plan.tf_messages)
    put("/tf", "tf2_msgs/msg/TFMessage", TF, g[0].stamp_ns, { transforms: g.map(transform) });
  const ps = plan.poses;
  for (const m of ps ? ps.messages : [])
    fgPut(put, ps.topic, ps.type, m.stamp_ns, F.poseMessage(ps.type, m, "cdr"), m.poses);
  for (const t of plan.odometry)
    put(plan.odometry_topic, "nav_msgs/msg/Odometry", ODOMETRY, t.stamp_ns, {
      header: header(t.stamp_ns, t.parent), child_frame_id: t.child,
      pose: { pose: { position: xyz(t.t), orientation: xyzw(t.q) }, covariance: zeros() },
      twist: { twist: { linear: xyz([0, 0, 0]), angular: xyz([0, 0, 0]) }, covariance: zeros() } });
  const imu = plan.imu;
  for (const t of imu ? imu.messages : [])
    put(imu.topic, "sensor_msgs/msg/Imu", IMU, t.stamp_ns, {
      header: header(t.stamp_ns, imu.frame), orientation: xyzw(t.q || [0, 0, 0, 0]),
      orientation_covariance: Float64Array.from([t.q ? 0 : -1, 0, 0, 0, 0, 0, 0, 0, 0]),
      angular_velocity: xyz(t.w), angular_velocity_covariance: new Float64Array(9),
      linear_acceleration: xyz([0, 0, 9.81]), linear_acceleration_covariance: new Float64Array(9) });
  const K = plan.K;
  plan.frames.forEach((f, i) => {
    put("/camera/depth/camera_info", "sensor_msgs/msg/CameraInfo", CAMINFO, f.stamp_ns, {
      header: header(f.stamp_ns, plan.frame_id), height: H, width: W, distortion_model: "plumb_bob",
      d: [0, 0, 0, 0, 0], k: K, r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
      p: [K[0], K[1], K[2], 0, K[3], K[4], K[5], 0, K[6], K[7], K[8], 0], binning_x: 0, binning_y: 0,
      roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false } });
    put("/camera/depth/image_raw", "sensor_msgs/msg/Image", IMAGE, BigInt(f.stamp_ns) + 1000n, {
      header: header(f.stamp_ns, plan.frame_id), height: H, width: W, encoding: "16UC1",
      is_bigendian: 0, step: 2 * W, data: raw.subarray(i * 2 * W * H, (i + 1) * 2 * W * H) });
  });
  return out.sort((a, b) => (a.time < b.time ? -1 : a.time > b.time ? 1 : 0));
}

// a topic's message and schema encodings (plan.fg.encoding: another for one topic)
function encodingOf(topic) {
  const e = (plan.fg || {}).encoding;
  return e && e.topic === topic ? e : { message: "cdr", schema: "ros2msg" };
}

async function writeMcap(file, msgs) {
  await M.zstd.isLoaded;
  const w = new M.FileWritable();
  const mw = new M.McapWriter({ writable: w, chunkSize: 1 << 20, compressChunk: M.compressors.zstd });
  await mw.start({ profile: "ros2", library: "depthao tests (@mcap/core)" });
  const enc = new TextEncoder(), channels = new Map();
  let seq = 0;
  for (const m of msgs) {
    if (!channels.has(m.topic)) {
      const e = encodingOf(m.topic);
      const sid = await mw.registerSchema({ name: m.type, encoding: e.schema, data: enc.encode(m.def) });
      channels.set(m.topic, await mw.registerChannel({ topic: m.topic, messageEncoding: e.message,
        schemaId: sid, metadata: new Map() }));
    }
    await mw.addMessage({ channelId: channels.get(m.topic), sequence: seq++, logTime: m.time,
      publishTime: m.time, data: m.bytes });
  }
  await mw.end();
  fs.writeFileSync(file, Buffer.concat(w.parts));
}

async function writeDb3(file, msgs) {
  const SQL = await initSqlJs();
  const db = new SQL.Database();
  db.run(D.SCHEMA);
  const ids = new Map();
  for (const m of msgs) {
    if (!ids.has(m.topic)) {
      ids.set(m.topic, ids.size + 1);
      db.run("INSERT INTO topics VALUES (?, ?, ?, ?, ?)",
        [ids.size, m.topic, m.type, encodingOf(m.topic).message, D.QOS]);
    }
    db.run("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
      [ids.get(m.topic), m.time, m.bytes]);
  }
  fs.writeFileSync(file, db.export());
  db.close();
}

(async () => {
  const msgs = messages();
  await writeMcap(process.argv[3], msgs);
  await writeDb3(process.argv[4], msgs);
})().catch((e) => { console.error(e); process.exit(1); });
