// SPDX-License-Identifier: MIT
// Shared by the foxglove suite: depthaod with a foxglove sink on the bundled
// recording, the reference client (@foxglove/ws-protocol over ws) from tests/js,
// Foxglove's own schemas (@foxglove/schemas) and a small 16-bit PNG reader.
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");
const zlib = require("zlib");
const { spawn } = require("child_process");

const SKIP = 77;
const root = process.env.DAO_SOURCE_ROOT || path.join(__dirname, "..", "..");
const modules = path.join(root, "tests", "js", "node_modules");

function fail(msg) {
  console.error("FAIL: " + msg);
  process.exit(1);
}

// The npm packages, or exit 77 with a message (npm ci in tests/js installs them).
function need(name) {
  try {
    return require(path.join(modules, name));
  } catch (e) {
    console.log(`SKIP: ${name} is not installed (cd tests/js && npm ci): ${e.message.split("\n")[0]}`);
    process.exit(SKIP);
  }
}

const WebSocket = need("ws");
const { FoxgloveClient } = need("@foxglove/ws-protocol");
const protobuf = need("protobufjs");
need("protobufjs/ext/descriptor");
const schemas = need("@foxglove/schemas/internal");

class Daemon {
  // depthaod looping the recording in real time into foxglove:0?OPTS (the port the
  // kernel picks, read from the log), with more arguments in `extra`
  constructor(depthaod, pluginDir, opts = "", extra = []) {
    this.rec = path.join(root, "recordings", "spheres-rolling.oni");
    this.logPath = path.join(fs.mkdtempSync(path.join(os.tmpdir(), "fox-")), "daemon.log");
    this.logFd = fs.openSync(this.logPath, "w");
    const uri = "foxglove:0" + (opts ? "?" + opts : "");
    this.proc = spawn(depthaod, ["--source", this.rec, "--loop", "--sink", "fox=" + uri,
      "--stats-interval", "0", ...extra],
      { stdio: ["ignore", this.logFd, this.logFd],
        env: Object.assign({}, process.env, { DEPTHAOD_PLUGIN_PATH: pluginDir, DEPTHAO_PLUGIN_PATH: pluginDir }) });
    this.exited = null;
    this.proc.on("exit", (code, sig) => { this.exited = { code, sig, at: process.hrtime.bigint() }; });
  }
  text() {
    return fs.readFileSync(this.logPath, "utf8");
  }
  async ready() {
    const until = Date.now() + 60000;
    for (;;) {
      const m = /open ws:\/\/127\.0\.0\.1:(\d+)/.exec(this.text());
      if (m) {
        this.port = Number(m[1]);
        return this.port;
      }
      if (this.exited) fail("depthaod exited: " + this.text());
      if (Date.now() > until) {
        this.proc.kill("SIGKILL");
        fail("the foxglove sink did not open in 60 s: " + this.text());
      }
      await sleep(100);
    }
  }
  // SIGTERM; resolves with the seconds until the process ended
  async stop() {
    if (this.exited) return 0;
    const t0 = process.hrtime.bigint();
    const done = new Promise((res) => this.proc.on("exit", res));
    this.proc.kill("SIGTERM");
    const timer = setTimeout(() => this.proc.kill("SIGKILL"), 20000);
    await done;
    clearTimeout(timer);
    return Number(this.exited.at - t0) / 1e9;
  }
}

function sleep(ms) {
  return new Promise((r) => setTimeout(r, ms));
}

// A reference client; resolves once it has the server info and the channels.
function connect(port, query = "") {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(`ws://127.0.0.1:${port}/${query}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const client = new FoxgloveClient({ ws });
    const st = { client, ws, info: null, channels: [], statuses: [], values: [] };
    // resolved once the greeting is whole: serverInfo, the channels and, on a connection
    // without control, the status saying so (sent after the channels: a test counting
    // statuses from here on must not see it arrive late)
    const greeted = () => st.info && st.channels.length &&
      (st.info.metadata?.control !== "false" || st.statuses.length > 0);
    client.on("error", (e) => reject(e));
    client.on("serverInfo", (i) => { st.info = i; });
    client.on("status", (s) => {
      st.statuses.push(s);
      if (greeted()) resolve(st);
    });
    client.on("parameterValues", (v) => st.values.push(v));
    client.on("advertise", (ch) => {
      st.channels.push(...ch);
      if (greeted()) resolve(st);
    });
    setTimeout(() => reject(new Error("no advertise within 20 s")), 20000);
  });
}

// Protobuf types from what a channel advertised (its FileDescriptorSet) and from
// Foxglove's published schemas, each able to decode the messages independently.
function advertisedRoot(channel) {
  const desc = protobuf.descriptor.FileDescriptorSet.decode(Buffer.from(channel.schema, "base64"));
  return protobuf.Root.fromDescriptor(desc);
}

function foxgloveRoot() {
  const r = new protobuf.Root();
  protobuf.parse(`syntax = "proto3"; package google.protobuf;
    message Timestamp { int64 seconds = 1; int32 nanos = 2; }`, r);
  for (const name of ["Vector3", "Quaternion", "Pose", "PackedElementField", "RawImage",
    "CompressedImage", "CameraCalibration", "PointCloud", "FrameTransform"]) {
    const text = schemas.generateProto(schemas.foxgloveMessageSchemas[name],
      name === "PackedElementField" ? [schemas.foxgloveEnumSchemas.NumericType] : [])
      .replace(/^import .*$/mg, "");
    protobuf.parse(text, r, { keepCase: true });
  }
  return r;
}

// A PNG's pixels: 8/16-bit gray or 8-bit RGB, not interlaced.
function readPng(file) {
  const b = fs.readFileSync(file);
  let pos = 8, w = 0, h = 0, depth = 0, ctype = 0;
  const idat = [];
  while (pos < b.length) {
    const len = b.readUInt32BE(pos), type = b.toString("latin1", pos + 4, pos + 8);
    const data = b.subarray(pos + 8, pos + 8 + len);
    if (type === "IHDR") {
      w = data.readUInt32BE(0); h = data.readUInt32BE(4); depth = data[8]; ctype = data[9];
    } else if (type === "IDAT") idat.push(data);
    pos += 12 + len;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const bpp = (ctype === 2 ? 3 : 1) * depth / 8, row = w * bpp;
  const out = Buffer.alloc(row * h);
  for (let y = 0; y < h; y++) {
    const f = raw[y * (row + 1)], src = raw.subarray(y * (row + 1) + 1, (y + 1) * (row + 1));
    const o = y * row;
    for (let x = 0; x < row; x++) {
      const a = x >= bpp ? out[o + x - bpp] : 0, up = y ? out[o - row + x] : 0;
      const c = x >= bpp && y ? out[o - row + x - bpp] : 0;
      let p;
      switch (f) {
        case 0: p = 0; break;
        case 1: p = a; break;
        case 2: p = up; break;
        case 3: p = (a + up) >> 1; break;
        case 4: { const pa = Math.abs(up - c), pb = Math.abs(a - c), pc = Math.abs(a + up - 2 * c);
          p = pa <= pb && pa <= pc ? a : pb <= pc ? up : c; break; }
        default: fail(`${file}: PNG filter ${f}`);
      }
      out[o + x] = (src[x] + p) & 255;
    }
  }
  return { width: w, height: h, depth, ctype, data: out };
}

module.exports = { SKIP, fail, need, Daemon, sleep, connect, advertisedRoot, foxgloveRoot, readPng,
  WebSocket, FoxgloveClient, protobuf };
