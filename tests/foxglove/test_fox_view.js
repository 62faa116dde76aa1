// SPDX-License-Identifier: MIT
// The headless Foxglove-protocol view (tools/foxview: @foxglove/ws-protocol and the
// advertised protobuf schemas, bundled by esbuild, in Debian's chromium): every panel
// goes live; the AO panel's pixels are the high bytes of the AO frame it last
// received (non-uniform), and AO frames the page received equal the PNGs the images
// sink wrote in the same loop.  Skips (77) without chromium, node modules or esbuild.
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");
const t = require("./foxtest.js");

const [depthaod, plugins] = process.argv.slice(2);
const view = require(path.join(__dirname, "..", "..", "tools", "foxview", "shot.js"));
if (!view.chromium()) {
  console.log("SKIP: chromium is not installed (apt-get install chromium)");
  process.exit(t.SKIP);
}
t.need("esbuild");

// a failure: thrown, so that the finally below closes chromium and the daemon first
function bad(msg) {
  throw new Error(msg);
}

async function main() {
  const pngDir = fs.mkdtempSync(path.join(os.tmpdir(), "foxview-ao-"));
  const d = new t.Daemon(depthaod, plugins, "", ["--sink", "ao=images:" + pngDir, "--stream", "ao=ao"]);
  let v = null;
  try {
    const port = await d.ready();
    v = await view.open(port, { timeoutMs: 120000 });
    await v.live();
    const st = await v.evaluate(`(() => { const s = window.foxview;
      return { channels: s.channels, params: s.params.length, cloud: s.cloudShown,
               shaded: s.shadedShown, errors: s.errors, caps: s.serverInfo.capabilities }; })()`);
    console.log(`page: ${st.params} parameters, ${st.shaded} shaded and ${st.cloud} cloud frames shown; ` +
      `capabilities ${st.caps.join(",")}`);
    if (st.errors.length) bad("page errors: " + st.errors.join("; "));
    await t.sleep(3000); /* more than a loop of the recording (16 frames) */
    await d.stop();
    await t.sleep(500);
    const r = await v.evaluate(`(() => { const s = window.foxview, cv = document.getElementById("ao");
      const px = cv.getContext("2d").getImageData(0, 0, cv.width, cv.height).data;
      const red = new Uint8Array(px.length / 4);
      for (let i = 0; i < red.length; i++) red[i] = px[4 * i];
      return { w: cv.width, h: cv.height, step: s.ao.step, enc: s.ao.encoding,
               canvas: foxviewB64(red), ring: s.aoRing.map((a) => foxviewB64(a)) }; })()`);
    check(r, pngDir);
  } finally {
    if (v) await v.close();
    await d.stop();
  }
}

function check(r, pngDir) {
  const canvas = Buffer.from(r.canvas, "base64");
  const ring = r.ring.map((b) => Buffer.from(b, "base64"));
  const last = ring[ring.length - 1];
  if (r.enc !== "mono16" || r.step !== 2 * r.w) bad(`AO ${r.enc}, step ${r.step} for width ${r.w}`);
  // the panel shows the last frame, 8 bits: the high byte of each little-endian sample
  let differ = 0;
  const seen = new Set();
  for (let i = 0; i < r.w * r.h; i++) {
    if (canvas[i] !== last[2 * i + 1]) differ++;
    seen.add(canvas[i]);
  }
  if (differ) bad(`${differ} AO panel pixels differ from the high bytes of the frame received`);
  if (seen.size < 16) bad(`the AO panel is near uniform: ${seen.size} grey levels`);
  // the frames received equal the PNGs of the last loop (16-bit, big-endian)
  const recv = new Set(ring.map((b) => { const be = Buffer.from(b); be.swap16(); return be.toString("base64"); }));
  const pngs = fs.readdirSync(pngDir).filter((f) => f.endsWith(".png"));
  let matched = 0, lastMatched = false;
  const lastBe = Buffer.from(last);
  lastBe.swap16();
  for (const f of pngs) {
    const p = t.readPng(path.join(pngDir, f));
    if (p.depth !== 16 || p.ctype !== 0 || p.width !== r.w || p.height !== r.h) bad(f + ": not a 16-bit gray PNG of the AO's size");
    const b64 = p.data.toString("base64");
    if (recv.has(b64)) matched++;
    if (b64 === lastBe.toString("base64")) lastMatched = true;
  }
  console.log(`AO panel: ${r.w}x${r.h}, ${seen.size} grey levels, equal to the high bytes of the last frame; ` +
    `${matched} of ${pngs.length} AO PNGs equal a frame the page showed` +
    (lastMatched ? " (the panel's frame among them)" : ""));
  if (!matched) bad(`none of the ${pngs.length} AO PNGs equals one of the ${ring.length} frames the page showed`);
}

main().catch((e) => t.fail(e.message || String(e)));
