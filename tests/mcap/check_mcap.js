// SPDX-License-Identifier: MIT
// Reads an MCAP file depthao wrote with the reference implementation (@mcap/core; CDR by
// @foxglove/rosmsg2-serialization, the schemas parsed by @foxglove/rosmsg) and checks it.
//   node check_mcap.js FILE [--ao DIR] [--shaded DIR] [--depth DIR] [--compression C] [--cloud]
//                        [--poses FILE [--pose-tolerance M]]
//     the indexed reader (footer, summary, statistics, chunk indexes, CRCs) and the
//     stream reader (CRCs of chunks and the data section) agree; every message decodes
//     with its schema; with --ao/--shaded the images equal the PNGs of those directories
//     (in name order), with --depth the 16UC1 filtered depth (/depthao/depth_filtered)
//     those of DIR (then "depth N" is printed too); the chunks use compression C; with
//     --poses the camera poses on /tf (tf2_msgs/msg/TFMessage, one transform each, just
//     before its AO image, the same stamp) equal those of FILE (a TUM trajectory,
//     depthao process --pose-out: tx ty tz qx qy qz qw, to its 9 and 12 decimals; with
//     --pose-tolerance within M metres and M in each quaternion component), one for each
//     AO image (then "tf N" is printed too); without it there must be none.
//   node check_mcap.js FILE --cut
//     a file cut short (no footer): the stream reader alone, up to where it ends.
// Prints "ao N shaded N info N points N chunks N"; exit 1 on a failed check, 77 without
// tests/js/node_modules.
"use strict";
const fs = require("fs");
const path = require("path");
const zlib = require("zlib");

const mods = path.join(__dirname, "..", "js", "node_modules");
let core, support, MessageReader, parse;
try {
  core = require(path.join(mods, "@mcap/core"));
  support = require(path.join(mods, "@mcap/support"));
  ({ MessageReader } = require(path.join(mods, "@foxglove/rosmsg2-serialization")));
  ({ parse } = require(path.join(mods, "@foxglove/rosmsg")));
} catch (e) {
  console.log("SKIP: tests/js/node_modules is not installed (cd tests/js && npm ci): " + e.message);
  process.exit(77);
}

const args = process.argv.slice(2);
const file = args[0];
const opt = (k) => { const i = args.indexOf(k); return i > 0 ? args[i + 1] : undefined; };
const fail = (msg) => { console.error("FAIL: " + msg); process.exit(1); };

// A PNG (8-bit RGB or 16-bit grey, not interlaced): { w, h, bpp, data } with 16-bit samples
// turned little-endian, as the Image messages hold them.
function readPng(p) {
  const b = fs.readFileSync(p);
  let off = 8, w = 0, h = 0, depth = 0, ctype = 0;
  const idat = [];
  while (off < b.length) {
    const len = b.readUInt32BE(off), type = b.toString("latin1", off + 4, off + 8);
    const d = b.subarray(off + 8, off + 8 + len);
    if (type === "IHDR") { w = d.readUInt32BE(0); h = d.readUInt32BE(4); depth = d[8]; ctype = d[9]; }
    if (type === "IDAT") idat.push(d);
    off += 12 + len;
  }
  const bpp = (ctype === 2 ? 3 : 1) * (depth / 8);
  const raw = zlib.inflateSync(Buffer.concat(idat)), row = w * bpp;
  const out = Buffer.alloc(row * h);
  for (let y = 0; y < h; y++) {
    const f = raw[y * (row + 1)], src = raw.subarray(y * (row + 1) + 1, (y + 1) * (row + 1));
    for (let x = 0; x < row; x++) {
      const a = x >= bpp ? out[y * row + x - bpp] : 0, up = y ? out[(y - 1) * row + x] : 0;
      const c = x >= bpp && y ? out[(y - 1) * row + x - bpp] : 0;
      let v = src[x];
      if (f === 1) v += a;
      else if (f === 2) v += up;
      else if (f === 3) v += (a + up) >> 1;
      else if (f === 4) {
        const pa = Math.abs(up - c), pb = Math.abs(a - c), pc = Math.abs(a + up - 2 * c);
        v += pa <= pb && pa <= pc ? a : pb <= pc ? up : c;
      }
      out[y * row + x] = v & 255;
    }
  }
  if (depth === 16) for (let i = 0; i < out.length; i += 2) { const t = out[i]; out[i] = out[i + 1]; out[i + 1] = t; }
  return { w, h, bpp, data: out };
}

function pngs(dir) {
  return dir ? fs.readdirSync(dir).filter((n) => n.endsWith(".png")).sort().map((n) => path.join(dir, n)) : null;
}

function decoders(schemas) {
  const m = new Map();
  for (const [id, s] of schemas) {
    if (s.encoding !== "ros2msg") fail(`schema ${s.name}: encoding ${s.encoding}`);
    m.set(id, new MessageReader(parse(new TextDecoder().decode(s.data), { ros2: true })));
  }
  return m;
}

// Checks one decoded message of a topic; counts in `n`.
function check(topic, msg, n, ref, logTime) {
  if (topic === "/tf") {
    const poses = ref.poses;
    if (!poses) fail("/tf: a camera pose in a recording made without motion (--poses not given)");
    if (msg.transforms.length !== 1) fail(`/tf: ${msg.transforms.length} transforms, want 1`);
    const t = msg.transforms[0], s = t.header.stamp;
    if (BigInt(s.sec) * 1000000000n + BigInt(s.nanosec) !== logTime) fail(`/tf: stamp != log time ${logTime}`);
    if (t.header.frame_id !== ref.poseFrame || t.child_frame_id !== ref.frameId)
      fail(`/tf: '${t.child_frame_id}' in '${t.header.frame_id}', want '${ref.frameId}' in '${ref.poseFrame}'`);
    if (n.tf >= poses.length) fail(`/tf: more poses than ${poses.length}`);
    const want = poses[n.tf], tr = t.transform.translation, q = t.transform.rotation;
    const got = [tr.x, tr.y, tr.z, q.x, q.y, q.z, q.w];
    for (let i = 0; i < 7; i++)
      if (Math.abs(got[i] - want[i]) > (ref.tolerance ?? (i < 3 ? 6e-10 : 6e-13)))
        fail(`/tf ${n.tf}: ${got} != the pose file's ${want}`);
    if (n.tf !== n.ao) fail(`/tf ${n.tf} does not come just before AO image ${n.ao}`);
    ref.tfStamp = logTime;
    n.tf++;
    return;
  }
  if (topic === "/depthao/ao" && ref.poses && (n.tf !== n.ao + 1 || ref.tfStamp !== logTime))
    fail(`AO image ${n.ao} without its pose just before it (${n.tf} poses)`);
  const stamp = BigInt(msg.header.stamp.sec) * 1000000000n + BigInt(msg.header.stamp.nanosec);
  if (stamp !== logTime) fail(`${topic}: header stamp ${stamp} != log time ${logTime}`);
  if (topic === "/depthao/ao" || topic === "/depthao/shaded" || topic === "/depthao/depth_filtered") {
    const ao = topic !== "/depthao/shaded", k = topic === "/depthao/ao" ? "ao" : ao ? "depth" : "shaded";
    const enc = k === "depth" ? "16UC1" : ao ? "mono16" : "rgb8", bpp = ao ? 2 : 3;
    if (msg.encoding !== enc || msg.step !== msg.width * bpp || msg.data.length !== msg.step * msg.height)
      fail(`${topic}: ${msg.encoding} ${msg.width}x${msg.height} step ${msg.step}`);
    const list = ref[k];
    if (list) {
      if (n[k] >= list.length) fail(`${topic}: more messages than PNGs (${list.length})`);
      const p = readPng(list[n[k]]);
      if (p.w !== msg.width || p.h !== msg.height || !Buffer.from(msg.data).equals(p.data))
        fail(`${topic} message ${n[k]} differs from ${list[n[k]]}`);
    }
    n[k]++;
  } else if (topic === "/depthao/camera_info") {
    if (!(msg.k[0] > 0 && msg.k[4] > 0 && msg.k[8] === 1 && msg.width > 0 && msg.distortion_model === "plumb_bob"))
      fail(`camera_info: K ${msg.k} ${msg.width}x${msg.height}`);
    n.info++;
  } else if (topic === "/depthao/points") {
    const names = msg.fields.map((f) => `${f.name}:${f.offset}:${f.datatype}`).join(",");
    if (names !== "x:0:7,y:4:7,z:8:7,ao:12:7" || msg.point_step !== 16 || msg.data.length !== 16 * msg.width)
      fail(`points: fields ${names}, ${msg.width} points, ${msg.data.length} bytes`);
    const dv = new DataView(msg.data.buffer, msg.data.byteOffset, msg.data.byteLength);
    for (let i = 0; i < msg.width; i++) {
      const z = dv.getFloat32(16 * i + 8, true), a = dv.getFloat32(16 * i + 12, true);
      if (!(z > 0) || !(a >= 0 && a <= 1)) fail(`points: point ${i} z ${z} ao ${a}`);
    }
    n.points++;
  } else {
    fail(`unexpected topic ${topic}`);
  }
}

// The stream reader over the whole file: records in order, CRCs checked.
function streamRead(buf, ref, cut) {
  const r = new core.McapStreamReader({ decompressHandlers: handlers, validateCrcs: true });
  r.append(buf);
  const schemas = new Map(), channels = new Map(), n = { ao: 0, shaded: 0, info: 0, points: 0, depth: 0, tf: 0, chunks: 0 };
  let dec = null, rec, end = false;
  while ((rec = r.nextRecord()) !== undefined) {
    if (rec.type === "Schema") schemas.set(rec.id, rec);
    else if (rec.type === "Channel") channels.set(rec.id, rec);
    else if (rec.type === "DataEnd") end = true;
    else if (rec.type === "Message") {
      dec = dec && dec.size === schemas.size ? dec : decoders(schemas);
      const ch = channels.get(rec.channelId);
      check(ch.topic, dec.get(ch.schemaId).readMessage(rec.data), n, ref, rec.logTime);
    }
  }
  if (!cut && (!end || !r.done())) fail("the stream reader did not reach the end of the file");
  return n;
}

let handlers;
(async () => {
  handlers = await support.loadDecompressHandlers();
  const buf = fs.readFileSync(file);
  const ref = { ao: pngs(opt("--ao")), shaded: pngs(opt("--shaded")), depth: pngs(opt("--depth")),
                poses: opt("--poses") ? fs.readFileSync(opt("--poses"), "utf8").split("\n")
                  .filter((l) => l.trim() && !l.startsWith("#")).map((l) => l.trim().split(/\s+/).slice(1).map(Number)) : null,
                poseFrame: opt("--pose-frame") || "depthao_odom",
                tolerance: opt("--pose-tolerance") !== undefined ? Number(opt("--pose-tolerance")) : undefined,
                frameId: opt("--frame-id") || "camera_depth_optical_frame" };
  if (args.includes("--cut")) {
    const n = streamRead(buf, {}, true);
    console.log(`ao ${n.ao} shaded ${n.shaded} info ${n.info} points ${n.points} chunks -`);
    return;
  }
  const s = streamRead(buf, ref, false);
  const readable = { size: async () => BigInt(buf.length), read: async (o, l) => buf.subarray(Number(o), Number(o + l)) };
  const rd = await core.McapIndexedReader.Initialize({ readable, decompressHandlers: handlers });
  if (rd.header.profile !== "ros2" || !rd.header.library.startsWith("depthao"))
    fail(`header: profile '${rd.header.profile}' library '${rd.header.library}'`);
  const st = rd.statistics;
  if (!st) fail("no statistics in the summary");
  for (const op of [3, 4, 11, 8]) if (!rd.summaryOffsetsByOpcode.has(op)) fail(`no summary offset for opcode ${op}`);
  const comp = opt("--compression");
  if (comp !== undefined && !rd.chunkIndexes.every((c) => c.compression === (comp === "none" ? "" : comp)))
    fail(`chunk compression: ${rd.chunkIndexes.map((c) => c.compression)}`);
  const dec = decoders(rd.schemasById), n = { ao: 0, shaded: 0, info: 0, points: 0, depth: 0, tf: 0, chunks: rd.chunkIndexes.length };
  let count = 0n;
  for await (const m of rd.readMessages({ validateCrcs: true })) {
    const ch = rd.channelsById.get(m.channelId);
    check(ch.topic, dec.get(ch.schemaId).readMessage(m.data), n, ref, m.logTime);
    count++;
  }
  if (count !== st.messageCount || Number(st.chunkCount) !== rd.chunkIndexes.length)
    fail(`statistics: ${st.messageCount} messages, ${st.chunkCount} chunks; read ${count}, ${rd.chunkIndexes.length}`);
  for (const k of ["ao", "shaded", "info", "points", "depth", "tf"])
    if (n[k] !== s[k]) fail(`${k}: the indexed reader read ${n[k]}, the stream reader ${s[k]}`);
  for (const k of ["ao", "shaded", "depth"])
    if (ref[k] && n[k] !== ref[k].length) fail(`${k}: ${n[k]} messages, ${ref[k].length} PNGs`);
  if (ref.poses && (n.tf !== ref.poses.length || n.tf !== n.ao))
    fail(`/tf: ${n.tf} poses for ${n.ao} AO images, the pose file has ${ref.poses.length}`);
  console.log(`ao ${n.ao} shaded ${n.shaded} info ${n.info} points ${n.points} chunks ${n.chunks}` +
              (ref.depth ? ` depth ${n.depth}` : "") + (ref.poses ? ` tf ${n.tf}` : ""));
})().catch((e) => fail(e.stack || String(e)));
