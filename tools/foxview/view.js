// SPDX-License-Identifier: MIT
// A headless stand-in for Foxglove's app (not available offline): a page that
// connects to a Foxglove WebSocket server with Foxglove's own client library
// (@foxglove/ws-protocol), decodes every channel with the schema the server
// advertised (its protobuf FileDescriptorSet, through protobufjs), and shows the
// AO image, the shaded JPEG, the point cloud (a pinhole projection on a canvas)
// and the parameter list, live.  Bundled for the browser with esbuild
// (tools/foxview/build.sh); test: tests/foxglove/test_fox_view.js.
// Not shipped in the daemon.  Open index.html?port=8765.
"use strict";
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const protobuf = require("protobufjs");
require("protobufjs/ext/descriptor");

const st = (window.foxview = { status: "connecting", ao: null, aoRing: [], aoShown: 0, shadedShown: 0,
  cloudShown: 0, params: [], channels: [], serverInfo: null, errors: [] });
const $ = (id) => document.getElementById(id);
function status(s) {
  st.status = s;
  $("status").textContent = s;
}

function typeFor(ch) {
  if (ch.encoding !== "protobuf") throw new Error(`${ch.topic}: encoding ${ch.encoding}`);
  const bin = Uint8Array.from(atob(ch.schema), (c) => c.charCodeAt(0));
  const set = protobuf.descriptor.FileDescriptorSet.decode(bin);
  return protobuf.Root.fromDescriptor(set).lookupType(ch.schemaName);
}

// mono16 -> 8-bit gray: the high byte (what Foxglove shows for mono16 without a range)
function showAo(m) {
  const w = m.width, h = m.height, d = m.data;
  const cv = $("ao");
  cv.width = w;
  cv.height = h;
  const ctx = cv.getContext("2d");
  const img = ctx.createImageData(w, h);
  const big = m.encoding === "mono16" ? 0 : 1;
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      const o = y * m.step + 2 * x;
      const v = big ? d[o] : d[o + 1]; /* the high byte of little-endian mono16 */
      const p = 4 * (y * w + x);
      img.data[p] = img.data[p + 1] = img.data[p + 2] = v;
      img.data[p + 3] = 255;
    }
  ctx.putImageData(img, 0, 0);
  st.ao = { width: w, height: h, step: m.step, encoding: m.encoding, data: d,
    stamp: Number(m.timestamp.seconds) * 1e3 + m.timestamp.nanos / 1e6 };
  st.aoRing.push(d); /* the last frames shown, for the test to compare with the PNGs */
  if (st.aoRing.length > 32) st.aoRing.shift();
  st.aoShown++;
}

function showShaded(m) {
  const blob = new Blob([m.data], { type: "image/" + m.format });
  createImageBitmap(blob).then((bmp) => {
    const cv = $("shaded");
    cv.width = bmp.width;
    cv.height = bmp.height;
    cv.getContext("2d").drawImage(bmp, 0, 0);
    st.shadedShown++;
  }, (e) => st.errors.push("jpeg: " + e));
}

let calib = null;
function showCloud(m) {
  const cv = $("cloud"), ctx = cv.getContext("2d");
  ctx.fillStyle = "#000";
  ctx.fillRect(0, 0, cv.width, cv.height);
  const off = {};
  for (const f of m.fields) off[f.name] = f.offset;
  const dv = new DataView(m.data.buffer, m.data.byteOffset, m.data.byteLength);
  const stride = m.point_stride ?? m.pointStride; /* protobufjs may camel-case the names */
  const n = stride ? Math.floor(m.data.byteLength / stride) : 0;
  /* the camera's view turned 0.4 rad about the vertical through the cloud's mean depth */
  let zm = 0, k = 0;
  for (let i = 0; i < n; i++) {
    const z = dv.getFloat32(i * stride + off.z, true);
    if (z > 0) { zm += z; k++; }
  }
  zm = k ? zm / k : 1;
  const c = Math.cos(0.4), s = Math.sin(0.4);
  const f = 0.6 * (calib ? calib.K[0] * cv.width / calib.width : cv.width); /* wider than the camera */
  for (let i = 0; i < n; i++) {
    const b = i * stride;
    const x = dv.getFloat32(b + off.x, true), y = dv.getFloat32(b + off.y, true);
    const z = dv.getFloat32(b + off.z, true), ao = dv.getFloat32(b + off.ao, true);
    const xr = c * x - s * (z - zm), zr = s * x + c * (z - zm) + zm;
    if (zr <= 0.05) continue;
    const u = cv.width / 2 + f * xr / zr, v = cv.height / 2 + f * y / zr;
    const g = Math.round(255 * Math.max(0, Math.min(1, ao)));
    ctx.fillStyle = `rgb(${g},${g},${Math.min(255, g + 40)})`;
    ctx.fillRect(u, v, 2, 2);
  }
  st.cloudShown++;
}

function showParams(list) {
  for (const p of list) {
    const i = st.params.findIndex((q) => q.name === p.name);
    if (i >= 0) st.params[i] = p;
    else st.params.push(p);
  }
  st.params.sort((a, b) => (a.name < b.name ? -1 : 1));
  $("params").textContent = st.params.map((p) => `${p.name} = ${JSON.stringify(p.value)}`).join("\n");
}

// base64 of bytes (for the test, through the DevTools protocol)
window.foxviewB64 = (u8) => {
  let out = "";
  for (let i = 0; i < u8.length; i += 0x8000)
    out += String.fromCharCode.apply(null, u8.subarray(i, i + 0x8000));
  return btoa(out);
};

function main() {
  const q = new URLSearchParams(location.search);
  const url = `ws://${q.get("host") || "127.0.0.1"}:${q.get("port") || "8765"}`;
  $("url").textContent = url;
  const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
  const subs = new Map();
  const show = { "/depthao/ao": showAo, "/depthao/shaded": showShaded, "/depthao/cloud": showCloud,
    "/depthao/calibration": (m) => { calib = m; } };
  client.on("open", () => status("connected"));
  client.on("error", (e) => { st.errors.push(String(e)); status("error"); });
  client.on("close", () => status("closed"));
  client.on("serverInfo", (i) => {
    st.serverInfo = i;
    $("info").textContent = `${i.name}; capabilities: ${(i.capabilities || []).join(", ")}`;
    if ((i.capabilities || []).includes("parameters")) client.getParameters([], "all");
  });
  client.on("parameterValues", (v) => showParams(v.parameters));
  client.on("advertise", (chs) => {
    for (const ch of chs) {
      st.channels.push({ topic: ch.topic, schemaName: ch.schemaName, encoding: ch.encoding });
      if (!show[ch.topic]) continue;
      try {
        subs.set(client.subscribe(ch.id), { type: typeFor(ch), show: show[ch.topic] });
      } catch (e) {
        st.errors.push(`${ch.topic}: ${e}`);
      }
    }
    $("channels").textContent = st.channels.map((c) => `${c.topic}  ${c.schemaName} (${c.encoding})`).join("\n");
  });
  client.on("message", ({ subscriptionId, data }) => {
    const s = subs.get(subscriptionId);
    if (!s) return;
    const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
    try {
      s.show(s.type.toObject(s.type.decode(bytes), { defaults: true, longs: Number }));
    } catch (e) {
      st.errors.push(String(e));
    }
    if (st.aoShown && st.shadedShown && st.cloudShown && st.params.length) status("live");
  });
}

main();
