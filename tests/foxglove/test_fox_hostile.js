// SPDX-License-Identifier: MIT
// Hostile clients of the foxglove sink (issue 38), each while reference clients
// watch the shaded channel; asserted on counts, never on times:
//  1. the client limit: with max-clients=3 a 4th client is refused at the
//     handshake, the 3 others keep receiving frames, and a slot freed is taken;
//  2. slowloris: 40 connections from 5 other addresses (127.0.0.2..6) trickle the
//     upgrade request a byte at a time and reconnect when cut; a legitimate client
//     still completes at least 18 of 20 handshakes;
//  3. a message over 16384 bytes: the connection is closed with 1009, the others
//     keep receiving;
//  4. a flood of 300 requests: a "too many requests" status (at most one a
//     second), the request after them dropped, the connection kept, and a
//     request answered again once the allowance is back;
//  5. text frames that are not strict JSON (not JSON, a NUL byte, \u0000, bytes
//     that are not UTF-8, a duplicate key, an escape in a key): each refused with
//     a status naming why, the connection kept and still answering.
// (A stalled client not slowing the others is test_fox_clients.js.)
// usage: node test_fox_hostile.js DEPTHAOD PLUGIN_DIRS
"use strict";
const net = require("net");
const t = require("./foxtest.js");

async function until(fn, what, ms = 15000) {
  const end = Date.now() + ms;
  while (!fn()) {
    if (Date.now() > end) t.fail("waited " + ms / 1000 + " s for " + what);
    await t.sleep(50);
  }
}

// A reference client counting the shaded channel's messages.
async function watch(port) {
  const c = await t.connect(port);
  const ch = c.channels.find((x) => x.topic === "/depthao/shaded");
  c.client.subscribe(ch.id);
  c.frames = 0;
  c.closed = null;
  c.client.on("message", () => c.frames++);
  c.ws.on("close", (code) => { c.closed = code; });
  return c;
}

// One handshake: "ok" once the channels are advertised, else why not (not thrown).
function tryConnect(port, ms = 8000) {
  return new Promise((resolve) => {
    const ws = new t.WebSocket(`ws://127.0.0.1:${port}/`, [t.FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const client = new t.FoxgloveClient({ ws });
    const timer = setTimeout(() => { ws.terminate(); resolve("no advertise in " + ms / 1000 + " s"); }, ms);
    const done = (r) => { clearTimeout(timer); resolve(r); };
    client.on("error", (e) => done("error: " + (e && e.message ? e.message : String(e))));
    ws.on("unexpected-response", (req, res) => { done("HTTP " + res.statusCode); req.destroy(); });
    client.on("advertise", () => { done("ok"); ws.close(); });
    ws.on("close", () => done("closed"));
  });
}

async function framesGrow(clients, what) {
  const before = clients.map((c) => c.frames);
  await until(() => clients.every((c, i) => c.frames >= before[i] + 5), what);
}

async function clientLimit(port) {
  const three = [await watch(port), await watch(port), await watch(port)];
  await framesGrow(three, "frames for 3 clients");
  const fourth = await tryConnect(port);
  if (fourth === "ok") t.fail("a 4th client was let in with max-clients=3");
  console.log(`client limit: the 4th client was refused (${fourth})`);
  await framesGrow(three, "frames for the 3 clients after the 4th was refused");
  three[2].client.close();
  await until(() => three[2].closed !== null, "a client's close");
  let again = "";
  for (let i = 0; i < 50 && again !== "ok"; i++) { // the server sees the close on its own pass
    again = await tryConnect(port);
    if (again !== "ok") await t.sleep(100);
  }
  if (again !== "ok") t.fail("the slot of a closed client was not free again: " + again);
  await framesGrow(three.slice(0, 2), "frames after a slot was taken again");
}

const UPGRADE = (port) => Buffer.from(`GET / HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n` +
  "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: c2xvd2xvcmlzc2xvd2xvcg==\r\n" +
  "Sec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n");

// 40 connections trickling their upgrade request, reconnecting when cut.
function slowloris(port) {
  const st = { stop: false, opened: 0, cut: 0, socks: new Set() };
  const req = UPGRADE(port);
  const open = (addr) => {
    if (st.stop) return;
    const s = net.connect({ host: "127.0.0.1", port, localAddress: addr });
    st.opened++;
    st.socks.add(s);
    let at = 0;
    const timer = setInterval(() => { if (at < req.length - 2) s.write(req.subarray(at, ++at)); }, 250);
    const again = () => {
      clearInterval(timer);
      if (!st.socks.delete(s)) return;
      st.cut++;
      setTimeout(() => open(addr), 50);
    };
    s.on("error", again);
    s.on("close", again);
  };
  for (let a = 2; a <= 6; a++) for (let i = 0; i < 8; i++) open(`127.0.0.${a}`);
  st.end = () => {
    st.stop = true;
    for (const s of st.socks) s.destroy();
  };
  return st;
}

async function slowlorisTest(port, watchers) {
  const st = slowloris(port);
  await t.sleep(1500); // every handshake slot taken
  let ok = 0;
  const why = [];
  for (let i = 0; i < 20; i++) {
    const r = await tryConnect(port);
    if (r === "ok") ok++;
    else why.push(r);
  }
  const opened = st.opened, cut = st.cut;
  st.end();
  console.log(`slowloris: ${opened} trickling connections opened, ${cut} cut by the sink; ` +
    `a legitimate client completed ${ok} of 20 handshakes ${why.length ? "(" + why.join("; ") + ")" : ""}`);
  if (ok < 18) t.fail(`under slowloris only ${ok} of 20 handshakes completed`);
  if (cut < 1) t.fail("no trickling connection was ever cut");
  await framesGrow(watchers, "frames for the watchers after slowloris");
}

async function oversized(port, watchers) {
  const big = await watch(port);
  big.ws.send(JSON.stringify({ op: "getParameters", parameterNames: ["radius"], id: "x".repeat(20000) }));
  await until(() => big.closed !== null, "the close of a client that sent 20000 bytes");
  if (big.closed !== 1009) t.fail(`an oversized message closed the connection with ${big.closed}, not 1009`);
  console.log("oversized: a 20000-byte message closed its connection with 1009");
  await framesGrow(watchers, "frames after an oversized message");
}

async function flood(port) {
  // requests that need no reply (an empty unsubscribe), so the client's reply queue
  // (32) is not what stops it: the rate limit is
  const c = await t.connect(port);
  let closed = null;
  c.ws.on("close", (code) => { closed = code; });
  const t0 = Date.now();
  const msg = JSON.stringify({ op: "unsubscribe", subscriptionIds: [] });
  for (let i = 0; i < 300; i++) c.ws.send(msg);
  c.client.getParameters(["radius"], "after");
  const limited = () => c.statuses.filter((s) => /too many requests/.test(s.message)).length;
  await until(() => limited() > 0 || closed !== null, "a rate-limit status");
  if (closed !== null) t.fail("a flood closed the connection: " + closed);
  // the getParameters sent after the flood was dropped with it; once the
  // allowance is back (20 a second), one is answered again
  let answered = false;
  c.client.on("parameterValues", (v) => { if (v.id === "later") answered = true; });
  for (let i = 0; i < 100 && !answered && closed === null; i++) {
    await t.sleep(200);
    c.client.getParameters(["radius"], "later");
  }
  const secs = (Date.now() - t0) / 1000;
  console.log(`flood: 300 requests; ${limited()} rate-limit statuses in ${secs.toFixed(1)} s; ` +
    `the first getParameters after it answered ${c.values.some((v) => v.id === "after") ? "(not dropped?)" : "(dropped)"}`);
  if (c.values.some((v) => v.id === "after")) t.fail("a request after 300 flooded ones was not dropped");
  if (!answered) t.fail("no request was answered after the flood");
  if (limited() > 1 + Math.ceil(secs)) t.fail(`${limited()} rate-limit statuses in ${secs.toFixed(1)} s (one a second)`);
  c.client.close();
}

async function badText(port) {
  const c = await t.connect(port);
  const cases = [
    ["not JSON", Buffer.from("hello"), /unexpected character at byte 0/],
    ["a NUL byte", Buffer.from('{"op":"get\0Parameters"}'), /NUL byte at byte 10/],
    ["\\u0000", Buffer.from('{"op":"subscribe\\u0000x"}'), /\\u0000 escape \(NUL\) at byte 16/],
    ["bytes that are not UTF-8", Buffer.from([0x7b, 0x22, 0x6f, 0x70, 0x22, 0x3a, 0x22, 0xff, 0x22, 0x7d]), /not UTF-8 at byte 7/],
    ["an overlong form", Buffer.from([0x22, 0xc0, 0xaf, 0x22]), /not UTF-8 at byte 1/],
    ["a duplicate key", Buffer.from('{"op":"getParameters","op":"subscribe"}'), /duplicate key at byte 22/],
    ["an escape in a key", Buffer.from('{"\\u006fp":"getParameters"}'), /escape inside a key at byte 2/],
    ["a lone surrogate", Buffer.from('{"op":"\\ud800"}'), /unpaired surrogate escape at byte 7/],
  ];
  let closedAs = null;
  c.ws.on("close", (code) => { closedAs = code; });
  for (const [what, bytes, want] of cases) {
    const n = c.statuses.length;
    c.ws.send(bytes, { binary: false });
    await until(() => c.statuses.length > n || closedAs !== null, "a reply to " + what);
    if (closedAs !== null) t.fail(`${what} closed the connection (${closedAs})`);
    const s = c.statuses[n];
    if (s.level !== 2 || !/^not strict JSON: /.test(s.message) || !want.test(s.message))
      t.fail(`${what}: status ${JSON.stringify(s)} does not match ${want}`);
  }
  c.client.getParameters(["radius"], "still");
  await until(() => c.values.find((v) => v.id === "still"), "an answer after the refused frames");
  console.log(`bad text frames: ${cases.length} refused with a status each, the connection kept`);
  c.client.close();
}

async function main() {
  const [depthaod, plugins] = process.argv.slice(2);
  const d3 = new t.Daemon(depthaod, plugins, "max-clients=3");
  await clientLimit(await d3.ready());
  await d3.stop();
  const d = new t.Daemon(depthaod, plugins);
  const port = await d.ready();
  const watchers = [await watch(port), await watch(port)];
  await slowlorisTest(port, watchers);
  await oversized(port, watchers);
  await flood(port);
  await badText(port);
  await framesGrow(watchers, "frames at the end");
  for (const c of watchers) if (c.closed !== null) t.fail("a watcher was closed: " + c.closed);
  await d.stop();
  const line = /foxglove: .* clients served.*/.exec(d.text());
  console.log(line ? line[0] : "no closing line");
  if (!line) t.fail("no closing line: " + d.text());
}

main().catch((e) => t.fail(e.stack || String(e)));
