// SPDX-License-Identifier: MIT
// Writes rosbag2 sqlite3 bags (.db3) as ROS 2's rosbag2_storage_default_plugins lays them out,
// with sql.js (SQLite compiled to WebAssembly) and CDR by @foxglove/rosmsg2-serialization, and
// reads each good one back with @foxglove/rosbag2-web (the reference reader) to check that its
// depth pixels are the frames written; the same frames as 16-bit PNGs (make_mcaps.js's):
//   d16.db3        /camera/depth/image_raw (Image 16UC1) and /camera/depth/camera_info
//   cdepth.db3     .../image_raw/compressedDepth (CompressedImage "16UC1; compressedDepth png")
//   color.db3      d16's plus /camera/color/image_raw (bgr8, stamps 10 ms after the depth);
//                  color.mcap the same messages in MCAP (make_mcaps.js's)
//   bag/           a rosbag2 directory: metadata.yaml and bag_0.db3 (d16's)
//   split2/        a split rosbag2 directory: d16's messages in split2_0.db3 (frames 0-1) and
//                  split2_1.db3 (frames 2-4)
//   zfile/, zmsg/  rosbag2 directories compressed by rosbag2's rules: d16.db3 as zfile_0.db3.zstd
//                  (compression_mode FILE); each message zstd-compressed (MESSAGE)
//   bagmcap/       a rosbag2 directory of MCAP storage: metadata.yaml and bagmcap_0.mcap
//   d32.db3        d16's frames as Image 32FC1 (metres, make_mcaps.js's d32)
//   fgcdr_16.db3, fgcdr_32.db3, fgcdr_png.db3  Foxglove's schemas as ROS 2 messages
//                  (foxglove_msgs/msg/RawImage 16UC1 or 32FC1, CompressedImage "png", and
//                  CameraCalibration, in CDR; make_mcaps.js's fgcdr_*), as ros2 bag record
//                  stores a node publishing them
//   damaged: notopics.db3 (no topics table), nocolumn.db3 (messages without timestamp),
//     texttime.db3 (a timestamp that is text), textdata.db3 (data that is text), badtopic.db3
//     (a topic_id no topic has), cut.db3 (a CDR message cut short), yuv.db3 (encoding yuv422),
//     fgcdr_cut.db3 (a foxglove_msgs/msg/RawImage cut short),
//     bigblob.db3 (a 2 MiB message), split/ (metadata.yaml of two files, neither there), splitmiss/ (its second file missing),
//     splitorder/ (its files listed out of time order), zbomb/ and zmbomb/ (zstd bombs: a file,
//     a message), znotz/ (a .zstd that is not), zlz4/ (compression_format lz4),
//     notsqlite.db3
// usage: node make_db3.js OUTDIR   (exit 77 when tests/js/node_modules is absent)
//        node make_db3.js OUTDIR --vga N: vga.db3 alone, N frames of 640x480 16UC1 at 30 fps
//        node make_db3.js FUZZDIR --seeds: the seeds of fuzz_db3_message and fuzz_foxglove
//        (FUZZDIR/corpus/db3_message, FUZZDIR/corpus/foxglove; the formats in those targets)
"use strict";
const fs = require("fs");
const path = require("path");

const M = require(path.join(__dirname, "..", "mcap", "make_mcaps.js"));
const { W, H, K, FRAMES, VGA, pixels, png16, stamp, logTime, IMAGE, COMPRESSED, CAMINFO, writer } = M;
let initSqlJs, Rosbag2, SqliteSqljs;
try {
  initSqlJs = require(path.join(M.mods, "sql.js"));
  ({ Rosbag2, SqliteSqljs } = require(path.join(M.mods, "@foxglove/rosbag2-web")));
} catch (e) {
  console.log("SKIP: tests/js/node_modules is not installed (cd tests/js && npm ci): " + e.message);
  process.exit(77);
}

// rosbag2's sqlite3 storage (schema version 3, as Humble writes it)
const SCHEMA = `
CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
INSERT INTO schema VALUES (3, 'humble');
CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, metadata TEXT NOT NULL);
CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
  serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,
  data BLOB NOT NULL);
CREATE INDEX timestamp_idx ON messages (timestamp ASC);`;
const QOS = "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 2\n";

const header = (i, frame = "camera_depth_optical_frame") => ({ stamp: stamp(i), frame_id: frame });
const camInfo = (i) => writer(CAMINFO).writeMessage({ header: header(i), height: H, width: W,
  distortion_model: "plumb_bob", d: [0, 0, 0, 0, 0], k: K, r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
  p: [K[0], 0, K[2], 0, 0, K[4], K[5], 0, 0, 0, 1, 0], binning_x: 0, binning_y: 0,
  roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false } });
const image = (i, encoding = "16UC1") => writer(IMAGE).writeMessage({ header: header(i), height: H,
  width: W, encoding, is_bigendian: 0, step: 2 * W, data: new Uint8Array(pixels(i).buffer) });
const cdepth = (i) => writer(COMPRESSED).writeMessage({ header: header(i),
  format: "16UC1; compressedDepth png", data: Buffer.concat([Buffer.alloc(12), png16(pixels(i))]) });
const color = (i) => {
  const bgr = new Uint8Array(3 * W * H);
  for (let k = 0; k < W * H; k++) { bgr[3 * k] = (k + i) & 255; bgr[3 * k + 1] = 40 * i; bgr[3 * k + 2] = 255 - (k & 255); }
  const s = stamp(i);
  return writer(IMAGE).writeMessage({ header: { stamp: { sec: s.sec, nanosec: s.nanosec + 10000000 },
    frame_id: "color" }, height: H, width: W, encoding: "bgr8", is_bigendian: 0, step: 3 * W, data: bgr });
};

// topics: [{ name, type, msg(i) -> bytes, dt: ns after the frame's time }]
// (frames from..to-1: one file of a split bag)
function bag(SQL, topics, from = 0, to = FRAMES) {
  const db = new SQL.Database();
  db.run(SCHEMA);
  topics.forEach((t, k) => db.run("INSERT INTO topics VALUES (?, ?, ?, 'cdr', ?)", [k + 1, t.name, t.type, QOS]));
  for (let i = from; i < to; i++)
    topics.forEach((t, k) => db.run("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
      [k + 1, logTime(i) + BigInt(t.dt || 0), t.msg(i)]));
  return db;
}
const save = (db, file) => { fs.writeFileSync(file, db.export()); db.close(); };

const INFO = { name: "/camera/depth/camera_info", type: "sensor_msgs/msg/CameraInfo", msg: camInfo };
const DEPTH = { name: "/camera/depth/image_raw", type: "sensor_msgs/msg/Image", msg: image, dt: 1000 };
const DEPTH32 = { ...DEPTH, msg: (i) => writer(IMAGE).writeMessage({ header: header(i), height: H,
  width: W, encoding: "32FC1", is_bigendian: 0, step: 4 * W, data: M.metres(pixels(i)) }) };
// Foxglove's schemas as ROS 2 messages: the depth (kind as make_mcaps.js's fgCdrDepth) and
// its calibration
const FG_INFO = { name: "/camera/depth/calibration", type: "foxglove_msgs/msg/CameraCalibration",
  msg: (i) => M.fgCdr("CameraCalibration", M.fgCdrCalibration(i)) };
const fgDepth = (kind) => ({ name: kind === "png" ? "/camera/depth/image_png" : "/camera/depth/image_raw",
  type: "foxglove_msgs/msg/" + (kind === "png" ? "CompressedImage" : "RawImage"), dt: 1000,
  msg: (i) => M.fgCdr(kind === "png" ? "CompressedImage" : "RawImage", M.fgCdrDepth(i, kind)) });

// The reference reader: every depth message decodes to the frame written.
async function check(file, topic) {
  const rb = new Rosbag2([new SqliteSqljs(fs.readFileSync(file))]);
  await rb.open();
  let n = 0;
  for await (const m of rb.readMessages({ topics: [topic] })) {
    const want = topic.endsWith("compressedDepth") ? png16(pixels(n)) : Buffer.from(pixels(n).buffer);
    const got = Buffer.from(m.value.data);
    if (!(topic.endsWith("compressedDepth") ? got.subarray(12) : got).equals(want))
      throw new Error(`${file}: message ${n} of ${topic} read back by @foxglove/rosbag2-web differs`);
    n++;
  }
  await rb.close();
  if (n !== FRAMES) throw new Error(`${file}: @foxglove/rosbag2-web read ${n} messages of ${topic}`);
}

function metadata(dir, storage, files, compression = "", mode = "") {
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, "metadata.yaml"), `rosbag2_bagfile_information:
  version: 5
  storage_identifier: ${storage}
  duration:
    nanoseconds: ${(FRAMES - 1) * 33333333}
  starting_time:
    nanoseconds_since_epoch: ${logTime(0)}
  message_count: ${2 * FRAMES}
  topics_with_message_count:
    - topic_metadata:
        name: /camera/depth/image_raw
        type: sensor_msgs/msg/Image
        serialization_format: cdr
        offered_qos_profiles: ""
      message_count: ${FRAMES}
  compression_format: "${compression}"
  compression_mode: "${mode}"
  relative_file_paths:
${files.map((f) => "    - " + f).join("\n")}
  files: []
`);
}

async function damaged(SQL, out) {
  const f = (n) => path.join(out, n);
  let db = bag(SQL, [INFO, DEPTH]);
  db.run("DROP TABLE topics");
  save(db, f("notopics.db3"));
  db = new SQL.Database();
  db.run(SCHEMA.replace("timestamp INTEGER NOT NULL,", "stamp INTEGER,").replace("(timestamp ASC)", "(stamp ASC)"));
  save(db, f("nocolumn.db3"));
  db = bag(SQL, [INFO, DEPTH]);
  db.run("UPDATE messages SET timestamp = 'soon' WHERE id = 4");
  save(db, f("texttime.db3"));
  db = bag(SQL, [INFO, DEPTH]);
  db.run("UPDATE messages SET data = 'pixels' WHERE id = 2");
  save(db, f("textdata.db3"));
  db = bag(SQL, [INFO, DEPTH]);
  db.run("UPDATE messages SET topic_id = 99 WHERE id = 3");
  save(db, f("badtopic.db3"));
  save(bag(SQL, [INFO, { ...DEPTH, msg: (i) => image(i).subarray(0, 2000) }]), f("cut.db3"));
  save(bag(SQL, [INFO, { ...DEPTH, msg: (i) => image(i, "yuv422") }]), f("yuv.db3"));
  const fg16 = fgDepth("16UC1");
  save(bag(SQL, [FG_INFO, { ...fg16, msg: (i) => fg16.msg(i).subarray(0, 2000) }]), f("fgcdr_cut.db3"));
  save(bag(SQL, [INFO, { ...DEPTH, msg: (i) => Buffer.concat([image(i), Buffer.alloc(2 << 20)]) }]), f("bigblob.db3"));
  metadata(f("split"), "sqlite3", ["split_0.db3", "split_1.db3"]);
  // split bags: the second file missing; the files listed out of time order
  metadata(f("splitmiss"), "sqlite3", ["s_0.db3", "s_1.db3"]);
  save(bag(SQL, [INFO, DEPTH], 0, 2), path.join(f("splitmiss"), "s_0.db3"));
  metadata(f("splitorder"), "sqlite3", ["s_1.db3", "s_0.db3"]);
  save(bag(SQL, [INFO, DEPTH], 0, 2), path.join(f("splitorder"), "s_0.db3"));
  save(bag(SQL, [INFO, DEPTH], 2, FRAMES), path.join(f("splitorder"), "s_1.db3"));
  // rosbag2's compression, hostile: zstd bombs (a file of 100 MiB of zeros, a message of
  // 8 MiB), a file that is not zstd, another format
  metadata(f("zbomb"), "sqlite3", ["zbomb_0.db3.zstd"], "zstd", "FILE");
  fs.writeFileSync(path.join(f("zbomb"), "zbomb_0.db3.zstd"), Buffer.from(M.zstd.compress(Buffer.alloc(100 << 20), 19)));
  metadata(f("zmbomb"), "sqlite3", ["zmbomb_0.db3"], "zstd", "MESSAGE");
  save(bag(SQL, [INFO, { ...DEPTH, msg: () => Buffer.from(M.zstd.compress(Buffer.alloc(8 << 20), 3)) }]),
    path.join(f("zmbomb"), "zmbomb_0.db3"));
  metadata(f("znotz"), "sqlite3", ["znotz_0.db3.zstd"], "zstd", "FILE");
  fs.writeFileSync(path.join(f("znotz"), "znotz_0.db3.zstd"), "not zstd\n");
  metadata(f("zlz4"), "sqlite3", ["zlz4_0.db3"], "lz4", "FILE");
  fs.writeFileSync(f("notsqlite.db3"), "not a database at all, just text\n");
}

// fuzz_db3_message: type byte, u16 + CameraInfo, u16 + depth message 0, depth message 1;
// fuzz_foxglove: schema/encoding byte (bit 3: foxglove_msgs in CDR), message
function seeds(dir) {
  const db3 = path.join(dir, "corpus", "db3_message"), fg = path.join(dir, "corpus", "foxglove");
  fs.mkdirSync(db3, { recursive: true });
  fs.mkdirSync(fg, { recursive: true });
  const u16 = (n) => Buffer.from([n & 255, n >> 8]);
  const seed = (type, info, d0, d1) => Buffer.concat([Buffer.from([type]), u16(info.length), info,
    u16(d0.length), d0, d1]);
  fs.writeFileSync(path.join(db3, "image_16uc1.bin"), seed(0, camInfo(0), image(0), image(1)));
  fs.writeFileSync(path.join(db3, "image_32fc1_mismatch.bin"), seed(0, camInfo(0), image(0), image(1, "32FC1")));
  fs.writeFileSync(path.join(db3, "compressed_png.bin"), seed(1, camInfo(0), cdepth(0), cdepth(1)));
  fs.writeFileSync(path.join(db3, "image_cut.bin"), seed(0, camInfo(0), image(0), image(1).subarray(0, 700)));
  const root = M.foxgloveRoot();
  const pb = (n, o) => Buffer.from(root.lookupType("foxglove." + n).encode(root.lookupType("foxglove." + n).fromObject(o)).finish());
  const js = (o) => Buffer.from(JSON.stringify(o));
  const put = (name, sel, msg) => fs.writeFileSync(path.join(fg, name), Buffer.concat([Buffer.from([sel]), msg]));
  put("raw_pb.bin", 0, pb("RawImage", M.fgDepth(0, false, false)));
  put("png_pb.bin", 1, pb("CompressedImage", M.fgDepth(0, false, true)));
  put("calibration_pb.bin", 2, pb("CameraCalibration", M.fgCalibration(0, false)));
  put("raw_json.bin", 4, js(M.fgDepth(0, true, false)));
  put("png_json.bin", 5, js(M.fgDepth(0, true, true)));
  put("calibration_json.bin", 6, js(M.fgCalibration(0, true)));
  put("raw_cdr.bin", 8, M.fgCdr("RawImage", M.fgCdrDepth(0, "16UC1")));
  put("raw32_cdr.bin", 8, M.fgCdr("RawImage", M.fgCdrDepth(0, "32FC1")));
  put("png_cdr.bin", 9, M.fgCdr("CompressedImage", M.fgCdrDepth(0, "png")));
  put("calibration_cdr.bin", 10, M.fgCdr("CameraCalibration", M.fgCdrCalibration(0)));
}

module.exports = { SCHEMA, QOS };

if (require.main === module) (async () => {
  const out = process.argv[2];
  if (process.argv[3] === "--seeds")
    return seeds(out);
  const SQL = await initSqlJs();
  // the reader's own SQLite build (@foxglove/sql.js), given its wasm (node has no fetch of files)
  await SqliteSqljs.Initialize({ wasmBinary: fs.readFileSync(path.join(M.mods, "@foxglove/sql.js/dist/sql-wasm.wasm")) });
  fs.mkdirSync(path.join(out, "png"), { recursive: true });
  if (VGA) {
    save(bag(SQL, [INFO, DEPTH]), path.join(out, "vga.db3"));
    return;
  }
  save(bag(SQL, [INFO, DEPTH]), path.join(out, "d16.db3"));
  await check(path.join(out, "d16.db3"), DEPTH.name);
  const CD = { name: "/camera/depth/image_raw/compressedDepth", type: "sensor_msgs/msg/CompressedImage", msg: cdepth, dt: 1000 };
  save(bag(SQL, [INFO, CD]), path.join(out, "cdepth.db3"));
  await check(path.join(out, "cdepth.db3"), CD.name);
  save(bag(SQL, [INFO, DEPTH32]), path.join(out, "d32.db3"));
  for (const kind of ["16UC1", "32FC1", "png"])
    save(bag(SQL, [FG_INFO, fgDepth(kind)]), path.join(out, "fgcdr_" + (kind === "png" ? "png" : kind.slice(0, 2)) + ".db3"));
  save(bag(SQL, [INFO, DEPTH, { name: "/camera/color/image_raw", type: "sensor_msgs/msg/Image", msg: color,
    dt: 10000000 }]), path.join(out, "color.db3"));
  metadata(path.join(out, "bag"), "sqlite3", ["bag_0.db3"]);
  fs.copyFileSync(path.join(out, "d16.db3"), path.join(out, "bag", "bag_0.db3"));
  // a split bag: frames 0-1 in its first file, 2-4 in its second, the CameraInfo in both
  metadata(path.join(out, "split2"), "sqlite3", ["split2_0.db3", "split2_1.db3"]);
  save(bag(SQL, [INFO, DEPTH], 0, 2), path.join(out, "split2", "split2_0.db3"));
  save(bag(SQL, [INFO, DEPTH], 2, FRAMES), path.join(out, "split2", "split2_1.db3"));
  metadata(path.join(out, "bagmcap"), "mcap", ["bagmcap_0.mcap"]);
  await M.zstd.isLoaded;
  // rosbag2's compression: the whole file (compression_mode FILE), or each message (MESSAGE)
  const zc = (b) => Buffer.from(M.zstd.compress(b, 3));
  metadata(path.join(out, "zfile"), "sqlite3", ["zfile_0.db3.zstd"], "zstd", "FILE");
  fs.writeFileSync(path.join(out, "zfile", "zfile_0.db3.zstd"), zc(fs.readFileSync(path.join(out, "d16.db3"))));
  metadata(path.join(out, "zmsg"), "sqlite3", ["zmsg_0.db3"], "zstd", "MESSAGE");
  save(bag(SQL, [{ ...INFO, msg: (i) => zc(camInfo(i)) }, { ...DEPTH, msg: (i) => zc(image(i)) }]),
    path.join(out, "zmsg", "zmsg_0.db3"));
  await M.write(path.join(out, "bagmcap", "bagmcap_0.mcap"), { chunkSize: 10000 }, M.raw);
  await M.write(path.join(out, "color.mcap"), { chunkSize: 10000 }, M.raw, true);
  await damaged(SQL, out);
  for (let i = 0; i < FRAMES; i++)
    fs.writeFileSync(path.join(out, "png", String(i).padStart(6, "0") + ".png"), png16(pixels(i)));
  fs.writeFileSync(path.join(out, "png", "camera.json"), JSON.stringify({ width: W, height: H,
    intrinsic_matrix: [K[0], K[3], K[6], K[1], K[4], K[7], K[2], K[5], K[8]] }));
})().catch((e) => { console.error(e); process.exit(1); });
