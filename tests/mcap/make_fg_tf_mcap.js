// SPDX-License-Identifier: MIT
// Writes a plan of test_cli_tf_poses.py as an MCAP file of Foxglove's schemas (@mcap/core, zstd
// chunks; protobuf by protobufjs with the .proto that @foxglove/schemas generates, or JSON with
// its JSON schemas): the depth as foxglove.RawImage 16UC1 (frame_id = the plan's frame_id) and
// its foxglove.CameraCalibration, /tf as foxglove.FrameTransform (a message a transform) and
// /tf_static as foxglove.FrameTransforms (a message a group).  No odometry (Foxglove has none),
// but plan.poses (optional: {topic, type PoseInFrame or PosesInFrame, messages: [{stamp_ns,
// frame, poses: [{q, t, fg}]}]}), the camera's poses as foxglove.PoseInFrame(s).
// PLAN_DIR/plan.json says what, PLAN_DIR/depth.raw holds the 16-bit frames.  plan.fg (optional):
//   static_topic  the static groups' topic instead of /tf_static
//   extra         [{topic, stamp_ns, transforms: [...]}]: more FrameTransforms messages
//   encoding      {topic, message, schema}: that channel's encodings (the bytes stay those of
//                 the file's own encoding)
// and a transform may carry fg: "stamp0" (written with timestamp 0), "truncate" (its
// message cut short inside its rotation), "nan" (w NaN; JSON: the literal NaN, as json-c
// reads it) or "nochild" (child_frame_id left out); a pose "nan" or "truncate" alike.
// make_tf_mcap.js writes the same as foxglove_msgs/msg/... in CDR with frameTransform,
// poseMessage and damaged.
// usage: node make_fg_tf_mcap.js PLAN_DIR OUT.mcap protobuf|json
//        node make_fg_tf_mcap.js --seeds TF_DIR [MCAP_DIR]   (the Foxglove seeds of fuzz_tf,
//        fuzz/corpus/tf, and of fuzz_mcap_reader, fuzz/corpus/mcap)
// (exit 77 without tests/js/node_modules)
"use strict";
const fs = require("fs");
const path = require("path");

const M = require(path.join(__dirname, "make_mcaps.js"));
const protobuf = require(path.join(M.mods, "protobufjs"));
require(path.join(M.mods, "protobufjs/ext/descriptor"));
const { generateProto } = require(path.join(M.mods, "@foxglove/schemas/dist/internal/generateProto"));
const { foxgloveMessageSchemas: S } = require(path.join(M.mods, "@foxglove/schemas/dist/internal/schemas"));
const JSONSCHEMA = require(path.join(M.mods, "@foxglove/schemas/jsonschema"));
const { generateRosMsgMergedSchema } = require(path.join(M.mods, "@foxglove/schemas/dist/internal/generateRos"));

const TYPES = ["RawImage", "CameraCalibration", "FrameTransform", "FrameTransforms", "Vector3", "Quaternion",
  "Pose", "PoseInFrame", "PosesInFrame"];

function root() {
  const r = new protobuf.Root();
  r.addJSON(protobuf.common["google/protobuf/timestamp.proto"].nested);
  for (const n of TYPES) protobuf.parse(generateProto(S[n], []), r, { keepCase: true });
  r.resolveAll();
  return r;
}

const split = (ns) => [BigInt(ns) / 1000000000n, BigInt(ns) % 1000000000n];
// a time in an encoding: json true (JSON), false (protobuf) or "cdr" (builtin_interfaces/Time)
const time = (ns, json) => {
  const [s, n] = split(ns);
  return json === "cdr" ? { sec: Number(s), nanosec: Number(n) }
    : json ? { sec: Number(s), nsec: Number(n) } : { seconds: Number(s), nanos: Number(n) };
};
const xyz = (v) => ({ x: v[0], y: v[1], z: v[2] });
const rotation = (x) => ({ x: x.q[0], y: x.q[1], z: x.q[2], w: x.fg === "nan" ? NaN : x.q[3] });

// a plan's transform as a FrameTransform object (CDR has every field: no child is "")
function frameTransform(t, json) {
  const m = { timestamp: time(t.fg === "stamp0" ? 0 : t.stamp_ns, json), parent_frame_id: t.parent,
    child_frame_id: t.child, translation: xyz(t.t), rotation: rotation(t) };
  if (t.fg === "nochild" && json === "cdr") m.child_frame_id = "";
  else if (t.fg === "nochild") delete m.child_frame_id;
  return m;
}

// a plan's pose message as a PoseInFrame or PosesInFrame object
function poseMessage(type, m, json) {
  const poses = m.poses.map((x) => ({ position: xyz(x.t), orientation: rotation(x) }));
  const o = { timestamp: time(m.stamp_ns, json), frame_id: m.frame };
  return type === "PoseInFrame" ? { ...o, pose: poses[0] } : { ...o, poses };
}

// bytes cut short inside the last rotation when a transform or pose asks for it
const damaged = (b, xs) => (xs.some((x) => x.fg === "truncate") ? b.subarray(0, b.length - 5) : b);

// encode: name, object -> bytes in the file's encoding
function encoder(json) {
  if (json)
    return (name, obj) => new TextEncoder().encode(JSON.stringify(obj).replace(/"w":null/g, '"w":NaN'));
  const r = root();
  return (name, obj) => { const T = r.lookupType("foxglove." + name); return T.encode(T.fromObject(obj)).finish(); };
}

// FrameTransform(s) bytes, cut short inside the last rotation when a transform asks for it
function transformsBytes(enc, name, ts, json) {
  const obj = name === "FrameTransform" ? frameTransform(ts[0], json)
    : { transforms: ts.map((t) => frameTransform(t, json)) };
  return damaged(enc(name, obj), ts);
}

async function writeFile(plan, raw, out, encoding) {
  const W = plan.width, H = plan.height, K = plan.K, fg = plan.fg || {};
  const json = encoding === "json", enc = encoder(json);
  const msgs = []; // { topic, type, time (BigInt), bytes }
  const put = (topic, type, t, bytes) => msgs.push({ topic, type, time: BigInt(t), bytes });
  for (const g of plan.tf_static_messages)
    put(fg.static_topic || "/tf_static", "FrameTransforms", plan.start_ns,
      transformsBytes(enc, "FrameTransforms", g, json));
  for (const g of plan.tf_messages)
    for (const t of g)
      put("/tf", "FrameTransform", t.stamp_ns, transformsBytes(enc, "FrameTransform", [t], json));
  for (const x of fg.extra || [])
    put(x.topic, "FrameTransforms", x.stamp_ns, transformsBytes(enc, "FrameTransforms", x.transforms, json));
  const ps = plan.poses;
  for (const m of ps ? ps.messages : [])
    put(ps.topic, ps.type, m.stamp_ns, damaged(enc(ps.type, poseMessage(ps.type, m, json)), m.poses));
  plan.frames.forEach((f, i) => {
    put("/camera/depth/calibration", "CameraCalibration", f.stamp_ns, enc("CameraCalibration", {
      timestamp: time(f.stamp_ns, json), frame_id: plan.frame_id, width: W, height: H,
      distortion_model: "plumb_bob", D: [0, 0, 0, 0, 0], K, R: [1, 0, 0, 0, 1, 0, 0, 0, 1],
      P: [K[0], K[1], K[2], 0, K[3], K[4], K[5], 0, K[6], K[7], K[8], 0] }));
    const px = raw.subarray(i * 2 * W * H, (i + 1) * 2 * W * H);
    put("/camera/depth/image_raw", "RawImage", BigInt(f.stamp_ns) + 1000n, enc("RawImage", {
      timestamp: time(f.stamp_ns, json), frame_id: plan.frame_id, width: W, height: H,
      encoding: "16UC1", step: 2 * W, data: json ? Buffer.from(px).toString("base64") : px }));
  });
  msgs.sort((a, b) => (a.time < b.time ? -1 : a.time > b.time ? 1 : 0));

  await M.zstd.isLoaded;
  const w = new M.FileWritable();
  const mw = new M.McapWriter({ writable: w, chunkSize: 1 << 20, compressChunk: M.compressors.zstd });
  await mw.start({ profile: "", library: "depthao tests (@mcap/core, @foxglove/schemas)" });
  const fds = protobuf.descriptor.FileDescriptorSet.encode(root().toDescriptor("proto3")).finish();
  const schemas = new Map(), channels = new Map();
  let seq = 0;
  for (const m of msgs) {
    const e = fg.encoding && fg.encoding.topic === m.topic ? fg.encoding
      : { message: encoding, schema: json ? "jsonschema" : "protobuf" };
    const key = m.type + " " + e.schema;
    if (!schemas.has(key))
      schemas.set(key, await mw.registerSchema({ name: "foxglove." + m.type, encoding: e.schema,
        data: e.schema === "jsonschema" ? new TextEncoder().encode(JSON.stringify(JSONSCHEMA[m.type])) : fds }));
    if (!channels.has(m.topic))
      channels.set(m.topic, await mw.registerChannel({ topic: m.topic, messageEncoding: e.message,
        schemaId: schemas.get(key), metadata: new Map() }));
    await mw.addMessage({ channelId: channels.get(m.topic), sequence: seq++, logTime: m.time,
      publishTime: m.time, data: m.bytes });
  }
  await mw.end();
  fs.writeFileSync(out, Buffer.concat(w.parts));
}

// fuzz_tf's seeds: a tag byte (8 | parser: 0 FrameTransform protobuf, 1 FrameTransforms
// protobuf, 2 FrameTransform JSON, 3 FrameTransforms JSON; 16 for DAO_TF_STATIC_IF_ALONE;
// 32 | 8 | the same of PoseInFrame(s); 32 | 0 FrameTransform, 1 PoseInFrame, 2 PosesInFrame
// as foxglove_msgs/msg/ in CDR);
// and with mcapDir fuzz_mcap_reader's: 8x6 depth, 2 frames, map -> odom (stamped 0, on
// /tf_static), odom -> cam on /tf, in protobuf and JSON
async function seeds(dir, mcapDir) {
  if (mcapDir) {
    const start = 1700000000000000000n, W = 8, H = 6;
    const tr = (ns, parent, child, fgFlag) => ({ stamp_ns: String(ns), parent, child, t: [0.5, 0, 0],
      q: [0, 0, 0.3826834323650898, 0.9238795325112867], fg: fgFlag });
    const plan = { width: W, height: H, frame_id: "cam", K: [5, 0, 3.5, 0, 5, 2.5, 0, 0, 1],
      start_ns: String(start), frames: [{ stamp_ns: String(start) }, { stamp_ns: String(start + 33333333n) }],
      tf_static_messages: [[tr(start, "map", "odom", "stamp0")]],
      tf_messages: [[tr(start, "odom", "cam")], [tr(start + 33333333n, "odom", "cam")]] };
    const raw = Buffer.alloc(2 * W * H * 2);
    for (let i = 0; i < W * H * 2; i++) raw.writeUInt16LE(500 + 3 * i, 2 * i);
    for (const e of ["protobuf", "json"])
      await writeFile(plan, raw, path.join(mcapDir, `fg_tf_${e === "json" ? "json" : "proto"}.mcap`), e);
  }
  fs.mkdirSync(dir, { recursive: true });
  const t = (child, ns, q) => ({ stamp_ns: String(ns), parent: child === "base" ? "odom" : "base",
    child, t: [1, 2, 3], q });
  const a = t("base", 1700000000000000000n, [0, 0, 0.3826834323650898, 0.9238795325112867]);
  const b = t("cam", 1700000000100000000n, [-0.5, 0.5, -0.5, 0.5]);
  const pose = { stamp_ns: a.stamp_ns, frame: "odom", poses: [{ q: b.q, t: [1, 2, 3] }] };
  for (const json of [false, true]) {
    const enc = encoder(json), tag = json ? 2 : 0, kind = json ? "json" : "proto";
    const write = (name, tagByte, bytes) =>
      fs.writeFileSync(path.join(dir, name), Buffer.concat([Buffer.from([tagByte]), Buffer.from(bytes)]));
    write(`fg_${kind}_transform.bin`, 8 | tag, transformsBytes(enc, "FrameTransform", [a], json));
    write(`fg_${kind}_transforms.bin`, 8 | tag | 1, transformsBytes(enc, "FrameTransforms", [a, b], json));
    write(`fg_${kind}_lone.bin`, 16 | 8 | tag | 1, transformsBytes(enc, "FrameTransforms",
      [a, { ...a, stamp_ns: "1700000000050000000" }, b], json));
    for (const [name, list] of [["PoseInFrame", 0], ["PosesInFrame", 1]])
      write(`fg_${kind}_${name === "PoseInFrame" ? "pose" : "poses"}.bin`, 32 | 8 | tag | list,
        enc(name, poseMessage(name, pose, json)));
  }
  const cdr = (name, obj) => M.writer(generateRosMsgMergedSchema(S[name], { rosVersion: 2 })).writeMessage(obj);
  const cdrSeed = (file, tagByte, bytes) =>
    fs.writeFileSync(path.join(dir, file), Buffer.concat([Buffer.from([tagByte]), Buffer.from(bytes)]));
  cdrSeed("fg_cdr_transform.bin", 32, cdr("FrameTransform", frameTransform(a, "cdr")));
  cdrSeed("fg_cdr_pose.bin", 32 | 1, cdr("PoseInFrame", poseMessage("PoseInFrame", pose, "cdr")));
  cdrSeed("fg_cdr_poses.bin", 32 | 2, cdr("PosesInFrame", poseMessage("PosesInFrame", pose, "cdr")));
}

module.exports = { frameTransform, poseMessage, damaged };
if (require.main !== module)
  return;
const main = process.argv[2] === "--seeds" ? () => seeds(process.argv[3], process.argv[4])
  : () => writeFile(JSON.parse(fs.readFileSync(path.join(process.argv[2], "plan.json"), "utf8")),
    fs.readFileSync(path.join(process.argv[2], "depth.raw")), process.argv[3], process.argv[4]);
main().catch((e) => {
  console.error(e);
  process.exit(1);
});
