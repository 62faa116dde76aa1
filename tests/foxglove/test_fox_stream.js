// SPDX-License-Identifier: MIT
// A reference client subscribes to every channel; each message decodes with the
// schema the channel advertised and with Foxglove's own, alike; the AO image equals
// the AO PNG depthaod writes of the same frame; the point cloud's ao field is that
// image's pixel under each point (projected with the calibration); the camera's pose
// (depth-temporal-motion icp) comes with each AO image, equal to the one depthaod's MCAP
// recorder writes on /tf for the same frame (@mcap/core, CDR by @foxglove/rosmsg2-
// serialization); the parameters read, change with the token and are refused read-only.
// usage: node test_fox_stream.js DEPTHAOD PLUGIN_DIRS
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");
const t = require("./foxtest.js");

async function main() {
  const [depthaod, plugins] = process.argv.slice(2);
  const pngDir = fs.mkdtempSync(path.join(os.tmpdir(), "fox-ao-"));
  const rec = path.join(pngDir, "rec.mcap");
  const d = new t.Daemon(depthaod, plugins, "token=s3cret&cloud-step=4",
    ["--sink", "ao=images:" + pngDir, "--stream", "ao=ao", "--sink", "rec=mcap:" + rec + "?frame_id=depthao",
      "--depth-temporal-motion", "icp"]);
  let tfs;
  try {
    tfs = await run(d, pngDir);
  } finally {
    await d.stop();
  }
  await checkRecordedPoses(rec, tfs);
  console.log("ok");
}

// The poses on /tf of depthaod's MCAP recording, by stamp: each /depthao/tf message the
// client got is the one recorded for the same frame (the wall clock the sink stamps with
// is the capture's; the recording keeps the frame's own time: matched by order of the
// translation instead, every client message must be one of the recording's poses).
async function checkRecordedPoses(rec, tfs) {
  const { McapIndexedReader } = require(path.join(__dirname, "..", "js", "node_modules", "@mcap/core"));
  const support = require(path.join(__dirname, "..", "js", "node_modules", "@mcap/support"));
  const { MessageReader } = require(path.join(__dirname, "..", "js", "node_modules", "@foxglove/rosmsg2-serialization"));
  const { parse } = require(path.join(__dirname, "..", "js", "node_modules", "@foxglove/rosmsg"));
  const buf = fs.readFileSync(rec);
  const readable = { size: async () => BigInt(buf.length), read: async (o, l) => buf.subarray(Number(o), Number(o + l)) };
  const rd = await McapIndexedReader.Initialize({ readable, decompressHandlers: await support.loadDecompressHandlers() });
  const recorded = new Map(); // pose -> its place in the recording
  for await (const m of rd.readMessages({ topics: ["/tf"] })) {
    const ch = rd.channelsById.get(m.channelId), sc = rd.schemasById.get(ch.schemaId);
    const msg = new MessageReader(parse(new TextDecoder().decode(sc.data), { ros2: true })).readMessage(m.data);
    const tr = msg.transforms[0];
    if (tr.header.frame_id !== "depthao_odom" || tr.child_frame_id !== "depthao")
      t.fail(`recorded /tf: '${tr.child_frame_id}' in '${tr.header.frame_id}'`);
    const v = tr.transform;
    const key = [v.translation.x, v.translation.y, v.translation.z, v.rotation.x, v.rotation.y, v.rotation.z, v.rotation.w].join(",");
    if (!recorded.has(key)) recorded.set(key, recorded.size);
  }
  if (!recorded.size) t.fail("the MCAP recording has no /tf");
  const seen = new Set();
  let last = -1;
  for (const tf of tfs) {
    const k = [tf.translation.x, tf.translation.y, tf.translation.z, tf.rotation.x, tf.rotation.y, tf.rotation.z, tf.rotation.w].join(",");
    if (!recorded.has(k)) t.fail("a pose on /depthao/tf that the recording does not have: " + k);
    // in the recording's order: a pose sent with another frame's image would break it
    if (recorded.get(k) <= last) t.fail(`pose ${seen.size} on /depthao/tf is the recording's ${recorded.get(k)}, after its ${last}`);
    last = recorded.get(k);
    seen.add(k);
  }
  // the camera stands still, but each accepted estimate moves the pose by a little: the
  // poses differ from frame to frame, so the match above tells them apart
  if (seen.size < 2) t.fail(`${tfs.length} poses on /depthao/tf, all the same: the check sees nothing`);
  console.log(`${tfs.length} poses on /depthao/tf, each one of the ${recorded.size} the MCAP recording has`);
}

function sub(st, topic) {
  const ch = st.channels.find((c) => c.topic === topic);
  if (!ch) t.fail("no channel " + topic + " in " + JSON.stringify(st.channels.map((c) => c.topic)));
  return ch;
}

async function run(d, pngDir) {
  const port = await d.ready();
  const a = await t.connect(port);
  const caps = a.info.capabilities;
  if (!caps.includes("parameters") || !caps.includes("parametersSubscribe"))
    t.fail("serverInfo capabilities: " + JSON.stringify(caps));
  const fox = t.foxgloveRoot();
  const want = { "/depthao/ao": "foxglove.RawImage", "/depthao/shaded": "foxglove.CompressedImage",
    "/depthao/calibration": "foxglove.CameraCalibration", "/depthao/cloud": "foxglove.PointCloud",
    "/depthao/tf": "foxglove.FrameTransform" };
  const got = {};
  const types = {};
  const aoAll = [];
  for (const [topic, schema] of Object.entries(want)) {
    const ch = sub(a, topic);
    if (ch.encoding !== "protobuf" || ch.schemaName !== schema)
      t.fail(`${topic}: ${ch.encoding} ${ch.schemaName}`);
    types[topic] = { mine: t.advertisedRoot(ch).lookupType(schema), theirs: fox.lookupType(schema) };
    const sid = a.client.subscribe(ch.id);
    got[sid] = { topic, msgs: [] };
  }
  a.client.on("message", (m) => {
    const g = got[m.subscriptionId];
    if (g.topic === "/depthao/ao") {
      aoAll.push(new Uint8Array(m.data.buffer, m.data.byteOffset, m.data.byteLength).slice());
      if (aoAll.length > 64) aoAll.shift();
    }
    if (g.msgs.length < 40)
      g.msgs.push({ ts: m.timestamp, bytes: new Uint8Array(m.data.buffer, m.data.byteOffset, m.data.byteLength).slice() });
  });
  const until = Date.now() + 30000;
  while (Object.values(got).some((g) => g.msgs.length < 8)) {
    if (Date.now() > until) t.fail("too few messages: " + JSON.stringify(Object.values(got).map((g) => [g.topic, g.msgs.length])));
    await t.sleep(100);
  }
  const dec = {};
  for (const g of Object.values(got)) {
    const ty = types[g.topic];
    dec[g.topic] = g.msgs.map((m) => {
      const x = ty.mine.toObject(ty.mine.decode(m.bytes), { longs: String, bytes: Buffer, enums: Number, defaults: true });
      const y = ty.theirs.toObject(ty.theirs.decode(m.bytes), { longs: String, bytes: Buffer, enums: Number, defaults: true });
      if (canon(x) !== canon(y))
        t.fail(`${g.topic}: the two schemas decode differently: ${canon(x).slice(0, 300)} vs ${canon(y).slice(0, 300)}`);
      x.ts = m.ts;
      return x;
    });
  }
  // the AO: mono16
  const aoByTs = new Map();
  for (const im of dec["/depthao/ao"]) {
    if (im.encoding !== "mono16" || im.step !== im.width * 2 || im.data.length !== im.step * im.height)
      t.fail(`AO image: ${im.encoding} ${im.width}x${im.height} step ${im.step}`);
    im.buf = Buffer.from(im.data);
    aoByTs.set(String(im.ts), im);
  }
  // the shaded image: a JPEG of the image's size
  for (const im of dec["/depthao/shaded"]) {
    const j = im.data;
    if (im.format !== "jpeg" || j[0] !== 0xff || j[1] !== 0xd8 || j[j.length - 2] !== 0xff || j[j.length - 1] !== 0xd9)
      t.fail("the shaded image is not a JPEG");
  }
  // the calibration and the cloud: each point's ao is the AO image's pixel under it
  const cal = dec["/depthao/calibration"][0];
  const [fx, , cx, , fy, cy] = cal.K;
  let checked = 0;
  for (const pc of dec["/depthao/cloud"]) {
    const names = pc.fields.map((f) => `${f.name}@${f.offset}:${f.type}`).join(",");
    if ((pc.point_stride ?? pc.pointStride) !== 16 || names !== "x@0:7,y@4:7,z@8:7,ao@12:7") t.fail("cloud fields " + names);
    const im = aoByTs.get(String(pc.ts));
    if (!im) continue;
    const v = new DataView(pc.data.buffer, pc.data.byteOffset, pc.data.byteLength);
    const n = pc.data.length / 16;
    if (!n) t.fail("an empty cloud");
    for (let i = 0; i < n; i++) {
      const x = v.getFloat32(i * 16, true), y = v.getFloat32(i * 16 + 4, true), z = v.getFloat32(i * 16 + 8, true);
      const ao = v.getFloat32(i * 16 + 12, true);
      const u = Math.round(x * fx / z + cx), w = Math.round(y * fy / z + cy);
      if (u % 4 || w % 4 || u < 0 || w < 0 || u >= cal.width || w >= cal.height) t.fail(`a point at pixel ${u},${w}`);
      const pix = im.buf.readUInt16LE((w * im.width + u) * 2);
      if (Math.abs(ao - pix / 65535) > 1e-6) t.fail(`ao ${ao} at ${u},${w}, the image has ${pix / 65535}`);
      checked++;
    }
  }
  if (!checked) t.fail("no cloud had the timestamp of an AO image");
  console.log(`${checked} cloud points checked against the AO images`);
  // the camera's pose: the images' frame in depthao_odom, stamped as an AO image
  let posed = 0;
  for (const tf of dec["/depthao/tf"]) {
    const q = tf.rotation, v = tf.translation;
    const parent = tf.parent_frame_id ?? tf.parentFrameId, child = tf.child_frame_id ?? tf.childFrameId;
    if (parent !== "depthao_odom" || child !== "depthao") t.fail(`tf: '${child}' in '${parent}'`);
    if (Math.abs(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w - 1) > 1e-9 ||
        ![v.x, v.y, v.z].every(Number.isFinite))
      t.fail("tf: not a pose: " + JSON.stringify(tf));
    posed += aoByTs.has(String(tf.ts));
  }
  if (!posed) t.fail("no pose had the timestamp of an AO image");

  // parameters: read; refused read-only; set with the token; subscribers told
  a.client.getParameters(["radius"], "g1");
  await until_(() => a.values.find((v) => v.id === "g1"), "getParameters reply");
  const r0 = a.values.find((v) => v.id === "g1").parameters[0].value;
  a.client.subscribeParameterUpdates(["radius"]);
  a.client.setParameters([{ name: "radius", value: 0.77 }], "s1");
  await until_(() => a.statuses.find((s) => s.level === 2 && /read-only/.test(s.message)), "read-only refusal");
  await until_(() => a.values.find((v) => v.id === "s1"), "values after the refusal");
  if (a.values.find((v) => v.id === "s1").parameters.find((p) => p.name === "radius").value !== r0)
    t.fail("a read-only client changed radius");
  const wrong = await t.connect(d.port, "?token=nope");
  wrong.client.setParameters([{ name: "radius", value: 0.77 }], "w1");
  await until_(() => wrong.statuses.find((s) => s.level === 2 && /read-only/.test(s.message)), "refusal with a wrong token");
  const b = await t.connect(d.port, "?token=s3cret");
  b.client.setParameters([{ name: "radius", value: 0.77 }], "s2");
  await until_(() => b.values.find((v) => v.id === "s2"), "setParameters reply");
  const set = b.values.find((v) => v.id === "s2").parameters.find((p) => p.name === "radius");
  if (Math.abs(set.value - 0.77) > 1e-6) t.fail("radius after set: " + JSON.stringify(set));
  await until_(() => a.values.find((v) => !v.id && v.parameters.some((p) => p.name === "radius" && Math.abs(p.value - 0.77) < 1e-6)),
    "the update to a subscriber");
  b.client.setParameters([{ name: "radius", value: 1e9 }], "s3");
  await until_(() => b.statuses.find((s) => s.level === 2 && /radius/.test(s.message)), "an out-of-range value refused");
  // the PNGs of the recording's 16 frames the images sink wrote last (the AO noise
  // pattern changes from loop to loop) equal AO images the client received last
  await d.stop();
  for (const c of [a, b, wrong]) c.client.close();
  const ty = types["/depthao/ao"].mine;
  const recv = new Set(aoAll.map((b) => {
    const be = Buffer.from(ty.decode(b).data);
    be.swap16(); // the PNG is big-endian, the message little-endian
    return be.toString("base64");
  }));
  const pngs = fs.readdirSync(pngDir).filter((f) => f.endsWith(".png"));
  let matched = 0;
  for (const f of pngs) {
    const p = t.readPng(path.join(pngDir, f));
    if (p.depth !== 16 || p.ctype !== 0) t.fail(f + ": not a 16-bit gray PNG");
    if (recv.has(p.data.toString("base64"))) matched++;
  }
  console.log(`${matched} of the ${pngs.length} AO PNGs of the last loop equal a received AO image`);
  if (matched < pngs.length / 2) t.fail(`only ${matched} of ${pngs.length} AO PNGs equal a received AO image`);
  return dec["/depthao/tf"];
}

// field names without case or underscores (protobufjs camel-cases descriptor names),
// keys sorted, bytes as hex
function canon(o) {
  if (Buffer.isBuffer(o) || o instanceof Uint8Array) return JSON.stringify(Buffer.from(o).toString("hex"));
  if (Array.isArray(o)) return "[" + o.map(canon).join(",") + "]";
  if (o && typeof o === "object")
    return "{" + Object.keys(o).map((k) => [k.replace(/_/g, "").toLowerCase(), o[k]]).sort((p, q) => (p[0] < q[0] ? -1 : 1))
      .map(([k, v]) => JSON.stringify(k) + ":" + canon(v)).join(",") + "}";
  return JSON.stringify(o);
}

async function until_(fn, what) {
  const end = Date.now() + 10000;
  while (!fn()) {
    if (Date.now() > end) t.fail("waited 10 s for " + what);
    await t.sleep(50);
  }
}

main().catch((e) => t.fail(e.stack || String(e)));
