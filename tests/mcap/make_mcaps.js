// SPDX-License-Identifier: MIT
// Writes MCAP files with the reference implementation (@mcap/core, CDR by
// @foxglove/rosmsg2-serialization) and the same depth frames as 16-bit PNGs:
//   d16_zstd.mcap  chunked, zstd (small chunks: several), summary and indexes
//   d16_lz4.mcap   chunked, lz4 frames (the lz4 tool)
//   d16_none.mcap  unchunked (messages in the data section)
//   d16_nosum.mcap chunked zstd, no summary, no indexes (read by a linear scan)
//   cdepth_png.mcap / cdepth_rvl.mcap  CompressedImage "16UC1; compressedDepth png|rvl"
//   color.mcap     d16_zstd's plus /camera/color/image_raw (bgr8, stamps 10 ms after the depth)
//   png/NNNNNN.png, png/camera.json
// Each with /camera/depth/camera_info (fx 60, fy 61, cx 31.5, cy 23.25).
// usage: node make_mcaps.js OUTDIR   (exit 77 when tests/js/node_modules is absent)
//        node make_mcaps.js OUTDIR --vga N: vga.mcap alone, N frames of 640x480 16UC1 at 30 fps
//        (zstd chunks of 4 MiB, as ros2 bag record writes), for the measurement (docs/perf/mcapr.md)
"use strict";
const fs = require("fs");
const path = require("path");
const zlib = require("zlib");
const { execFileSync } = require("child_process");

const mods = path.join(__dirname, "..", "js", "node_modules");
let McapWriter, MessageWriter, parse, zstd;
try {
  ({ McapWriter } = require(path.join(mods, "@mcap/core")));
  ({ MessageWriter } = require(path.join(mods, "@foxglove/rosmsg2-serialization")));
  ({ parse } = require(path.join(mods, "@foxglove/rosmsg")));
  zstd = require(path.join(mods, "@foxglove/wasm-zstd"));
} catch (e) {
  console.log("SKIP: tests/js/node_modules is not installed (cd tests/js && npm ci): " + e.message);
  process.exit(77);
}

const VGA = process.argv[3] === "--vga";
const W = VGA ? 640 : 64, H = VGA ? 480 : 48, FRAMES = VGA ? Number(process.argv[4]) : 5;
const K = [60, 0, 31.5, 0, 61, 23.25, 0, 0, 1];
const depthCount = VGA
  ? (x, y, i) => ((x * 7 + y * 3 + i * 5) % 97 === 0 ? 0 : 800 + ((x * x + 3 * y * y) >> 7) % 900 + 20 * ((x + i * 4) >> 5 & 7))
  : (x, y, i) => (x === y ? 0 : 500 + 7 * x + 13 * y + 100 * i);
const pixels = (i) => {
  const a = new Uint16Array(W * H);
  for (let y = 0; y < H; y++) for (let x = 0; x < W; x++) a[y * W + x] = depthCount(x, y, i);
  return a;
};
const stamp = (i) => ({ sec: 1700000000 + Math.floor(i / 30), nanosec: (i % 30) * 33333333 });
const logTime = (i) => 1700000000n * 1000000000n + BigInt(i * 33333333);

const TIME = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";
const HEADER = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n";
const SEP = "================================================================================\n";
const IMAGE = "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n" +
  "uint8 is_bigendian\nuint32 step\nuint8[] data\n" + SEP + HEADER + SEP + TIME;
const COMPRESSED = "std_msgs/Header header\nstring format\nuint8[] data\n" + SEP + HEADER + SEP + TIME;
const CAMINFO = "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n" +
  "float64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\n" +
  "sensor_msgs/RegionOfInterest roi\n" + SEP + HEADER + SEP + TIME + SEP +
  "MSG: sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\n" +
  "uint32 width\nbool do_rectify\n";
const writer = (def) => new MessageWriter(parse(def, { ros2: true }));

// a 16-bit grey PNG (big-endian samples, filter 0)
const crcTable = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
const crc32 = (buf) => {
  let c = 0xffffffff;
  for (const b of buf) c = crcTable[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
};
function png16(px) {
  const chunk = (type, data) => {
    const len = Buffer.alloc(4);
    len.writeUInt32BE(data.length);
    const td = Buffer.concat([Buffer.from(type), data]);
    const crc = Buffer.alloc(4);
    crc.writeUInt32BE(crc32(td));
    return Buffer.concat([len, td, crc]);
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(W, 0);
  ihdr.writeUInt32BE(H, 4);
  ihdr[8] = 16; // bit depth; colour type 0 (grey), no interlace
  const raw = Buffer.alloc(H * (1 + 2 * W));
  for (let y = 0; y < H; y++)
    for (let x = 0; x < W; x++) raw.writeUInt16BE(px[y * W + x], y * (1 + 2 * W) + 1 + 2 * x);
  return Buffer.concat([Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]),
    chunk("IHDR", ihdr), chunk("IDAT", zlib.deflateSync(raw)), chunk("IEND", Buffer.alloc(0))]);
}

// RVL as compressed_depth_image_transport writes it (see src/io/mcap/compressed_depth.h)
function rvl(px) {
  const words = [];
  let word = 0, nibbles = 0;
  const put = (v) => {
    do {
      let nib = v & 7;
      v >>>= 3;
      if (v) nib |= 8;
      word = ((word << 4) | nib) >>> 0;
      if (++nibbles === 8) { words.push(word); word = 0; nibbles = 0; }
    } while (v);
  };
  let i = 0, prev = 0;
  while (i < px.length) {
    let z = 0;
    while (i + z < px.length && px[i + z] === 0) z++;
    put(z);
    i += z;
    let nz = 0;
    while (i + nz < px.length && px[i + nz] !== 0) nz++;
    put(nz);
    for (let k = 0; k < nz; k++, i++) {
      const d = px[i] - prev;
      put(((d << 1) ^ (d >> 31)) >>> 0);
      prev = px[i];
    }
  }
  if (nibbles) words.push((word << (4 * (8 - nibbles))) >>> 0);
  const out = Buffer.alloc(8 + 4 * words.length);
  out.writeUInt32LE(W, 0);
  out.writeUInt32LE(H, 4);
  words.forEach((w, k) => out.writeUInt32LE(w, 8 + 4 * k));
  return out;
}

class FileWritable {
  constructor() { this.parts = []; this.pos = 0n; }
  position() { return this.pos; }
  async write(buf) { this.parts.push(Buffer.from(buf)); this.pos += BigInt(buf.byteLength); }
}

const compressors = {
  zstd: (d) => ({ compression: "zstd", compressedData: zstd.compress(d, 3) }),
  lz4: (d) => ({ compression: "lz4", compressedData: execFileSync("lz4", ["-c", "-q"], { input: d }) }),
};

async function write(file, opts, depth, color) {
  const w = new FileWritable();
  const mw = new McapWriter({ writable: w, ...opts });
  await mw.start({ profile: "ros2", library: "depthao tests (@mcap/core)" });
  const enc = new TextEncoder();
  const img = await mw.registerSchema({ name: depth.schema, encoding: "ros2msg", data: enc.encode(depth.def) });
  const ci = await mw.registerSchema({ name: "sensor_msgs/msg/CameraInfo", encoding: "ros2msg", data: enc.encode(CAMINFO) });
  const dch = await mw.registerChannel({ topic: depth.topic, messageEncoding: "cdr", schemaId: img, metadata: new Map() });
  const cch = await mw.registerChannel({ topic: "/camera/depth/camera_info", messageEncoding: "cdr", schemaId: ci, metadata: new Map() });
  const ciw = writer(CAMINFO), dw = writer(depth.def);
  let colch;
  if (color)
    colch = await mw.registerChannel({ topic: "/camera/color/image_raw", messageEncoding: "cdr", schemaId: img, metadata: new Map() });
  for (let i = 0; i < FRAMES; i++) {
    const header = { stamp: stamp(i), frame_id: "camera_depth_optical_frame" };
    await mw.addMessage({ channelId: cch, sequence: i, logTime: logTime(i), publishTime: logTime(i),
      data: ciw.writeMessage({ header, height: H, width: W, distortion_model: "plumb_bob",
        d: [0, 0, 0, 0, 0], k: K, r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
        p: [K[0], 0, K[2], 0, 0, K[4], K[5], 0, 0, 0, 1, 0], binning_x: 0, binning_y: 0,
        roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false } }) });
    await mw.addMessage({ channelId: dch, sequence: i, logTime: logTime(i) + 1000n,
      publishTime: logTime(i), data: dw.writeMessage(depth.msg(header, pixels(i))) });
    if (color) {
      const bgr = new Uint8Array(3 * W * H);
      for (let k = 0; k < W * H; k++) { bgr[3 * k] = (k + i) & 255; bgr[3 * k + 1] = 40 * i; bgr[3 * k + 2] = 255 - (k & 255); }
      const cs = { sec: header.stamp.sec, nanosec: header.stamp.nanosec + 10000000 };
      await mw.addMessage({ channelId: colch, sequence: i, logTime: logTime(i) + 10000000n, publishTime: logTime(i),
        data: dw.writeMessage({ header: { stamp: cs, frame_id: "color" }, height: H, width: W, encoding: "bgr8",
          is_bigendian: 0, step: 3 * W, data: bgr }) });
    }
  }
  await mw.end();
  fs.writeFileSync(file, Buffer.concat(w.parts));
}

const raw = {
  schema: "sensor_msgs/msg/Image", def: IMAGE, topic: "/camera/depth/image_raw",
  msg: (header, px) => ({ header, height: H, width: W, encoding: "16UC1", is_bigendian: 0,
    step: 2 * W, data: new Uint8Array(px.buffer) }),
};
const cdepth = (codec) => ({
  schema: "sensor_msgs/msg/CompressedImage", def: COMPRESSED,
  topic: "/camera/depth/image_raw/compressedDepth",
  msg: (header, px) => ({ header, format: "16UC1; compressedDepth " + codec,
    data: Buffer.concat([Buffer.alloc(12), codec === "png" ? png16(px) : rvl(px)]) }),
});

(async () => {
  const out = process.argv[2];
  await zstd.isLoaded;
  fs.mkdirSync(path.join(out, "png"), { recursive: true });
  if (VGA) {
    await write(path.join(out, "vga.mcap"), { chunkSize: 4 << 20, compressChunk: compressors.zstd }, raw);
    return;
  }
  const small = { chunkSize: 10000 };
  await write(path.join(out, "d16_zstd.mcap"), { ...small, compressChunk: compressors.zstd }, raw);
  await write(path.join(out, "d16_lz4.mcap"), { ...small, compressChunk: compressors.lz4 }, raw);
  await write(path.join(out, "d16_none.mcap"), { useChunks: false }, raw);
  await write(path.join(out, "d16_nosum.mcap"), { ...small, compressChunk: compressors.zstd,
    useStatistics: false, useSummaryOffsets: false, useChunkIndex: false, useMessageIndex: false,
    repeatSchemas: false, repeatChannels: false, useAttachmentIndex: false, useMetadataIndex: false }, raw);
  await write(path.join(out, "color.mcap"), { ...small, compressChunk: compressors.zstd }, raw, true);
  await write(path.join(out, "cdepth_png.mcap"), { compressChunk: compressors.zstd }, cdepth("png"));
  await write(path.join(out, "cdepth_rvl.mcap"), { compressChunk: compressors.lz4 }, cdepth("rvl"));
  for (let i = 0; i < FRAMES; i++)
    fs.writeFileSync(path.join(out, "png", String(i).padStart(6, "0") + ".png"), png16(pixels(i)));
  fs.writeFileSync(path.join(out, "png", "camera.json"), JSON.stringify({ width: W, height: H,
    intrinsic_matrix: [K[0], K[3], K[6], K[1], K[4], K[7], K[2], K[5], K[8]] }));
})().catch((e) => { console.error(e); process.exit(1); });
