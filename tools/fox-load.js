// SPDX-License-Identifier: MIT
// The foxglove sink under load: depthaod looping the bundled recording in real time
// (640x480, 30 fps), then for each client count N a fresh daemon and N reference
// clients (@foxglove/ws-protocol from tests/js) subscribed to /depthao/ao and
// /depthao/shaded, optionally one of them stalled (subscribed, never reading).
// Prints one short table: per round the frames and frame rate each client got,
// the latency from capture to receipt (the message timestamp is the capture time,
// CLOCK_REALTIME of the daemon; receipt is read on the same host's clock), the
// sink's own capture -> socket latency (its close log), and the CPU of the sink's
// threads (sink:fox, fox:lws) and of the whole daemon.  docs/perf/foxlat.md.
//
//   node tools/fox-load.js BUILD/tools/depthaod/depthaod BUILD/plugins/foxglove \
//        [--clients 0,1,5,10] [--seconds 10] [--stall]
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");
const { performance } = require("perf_hooks");
const t = require(path.join(__dirname, "..", "tests", "foxglove", "foxtest.js"));

function usage(msg) {
  console.error(`fox-load: ${msg}\nusage: node tools/fox-load.js DEPTHAOD PLUGIN_DIR ` +
    "[--clients 0,1,5,10] [--seconds 10] [--warmup 3] [--stall]");
  process.exit(2);
}

function parseArgs(argv) {
  const a = { clients: [0, 1, 5, 10], seconds: 10, warmup: 3, stall: false, pos: [] };
  for (let i = 0; i < argv.length; i++) {
    const k = argv[i];
    if (k === "--stall") a.stall = true;
    else if (k === "--clients") a.clients = String(argv[++i]).split(",").map(Number);
    else if (k === "--seconds") a.seconds = Number(argv[++i]);
    else if (k === "--warmup") a.warmup = Number(argv[++i]);
    else if (k.startsWith("--")) usage(`unknown option ${k}`);
    else a.pos.push(k);
  }
  if (a.pos.length !== 2) usage("give the depthaod binary and the foxglove plugin directory");
  if (a.clients.some((n) => !Number.isInteger(n) || n < 0 || n > 16))
    usage("--clients: counts 0..16 (the sink's default max-clients is 16)");
  if (!(a.seconds > 0) || !(a.warmup >= 0)) usage("--seconds > 0 and --warmup >= 0");
  return a;
}

// CPU seconds of the daemon's threads: the sink's (by name) and all of them.
function cpu(pid) {
  const r = { sink: 0, lws: 0, all: 0 };
  for (const tid of fs.readdirSync(`/proc/${pid}/task`)) {
    let comm, ns;
    try {
      comm = fs.readFileSync(`/proc/${pid}/task/${tid}/comm`, "utf8").trim();
      ns = Number(fs.readFileSync(`/proc/${pid}/task/${tid}/schedstat`, "utf8").split(" ")[0]);
    } catch (e) {
      continue; /* a thread that ended meanwhile */
    }
    r.all += ns / 1e9;
    if (comm === "sink:fox" || comm === "fox:lws") r.sink += ns / 1e9;
    if (comm === "fox:lws") r.lws += ns / 1e9;
  }
  return r;
}

function nowNs() {
  return BigInt(Math.round((performance.timeOrigin + performance.now()) * 1e6));
}

function quantile(sorted, q) {
  return sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))] : NaN;
}

async function round(a, n) {
  const d = new t.Daemon(a.pos[0], a.pos[1], "");
  const port = await d.ready();
  const clients = [];
  for (let i = 0; i < n; i++) {
    const c = await t.connect(port);
    c.stalled = a.stall && n >= 2 && i === n - 1; /* a stalled one among others */
    c.frames = { "/depthao/ao": 0, "/depthao/shaded": 0 };
    c.lat = [];
    c.measuring = false;
    const bySub = new Map();
    for (const ch of c.channels)
      if (ch.topic in c.frames) bySub.set(c.client.subscribe(ch.id), ch.topic);
    c.client.on("message", (m) => {
      if (!c.measuring) return;
      const rx = nowNs();
      c.frames[bySub.get(m.subscriptionId)]++;
      c.lat.push(Number(rx - BigInt(m.timestamp)) / 1e6);
    });
    if (c.stalled) c.ws._socket.pause();
    clients.push(c);
  }
  await t.sleep(a.warmup * 1000);
  const c0 = cpu(d.proc.pid), t0 = performance.now();
  for (const c of clients) c.measuring = true;
  await t.sleep(a.seconds * 1000);
  for (const c of clients) c.measuring = false;
  const c1 = cpu(d.proc.pid), secs = (performance.now() - t0) / 1000;
  for (const c of clients) c.ws.terminate();
  await d.stop();
  const m = /latency capture -> socket median ([\d.]+) ms, p99 ([\d.]+) ms/.exec(d.text());
  const dropped = /(\d+) dropped/.exec(d.text());
  const inSink = /of it in the sink median ([\d.]+) ms, p99 [\d.]+ ms; building the message median ([\d.]+) ms/.exec(d.text());
  const live = clients.filter((c) => !c.stalled);
  const lat = live.flatMap((c) => c.lat).sort((x, y) => x - y);
  const fps = live.map((c) => c.frames["/depthao/ao"] / secs);
  return {
    n, secs, stall: clients.some((c) => c.stalled),
    aoFps: fps.length ? Math.min(...fps) : NaN, aoFpsMax: fps.length ? Math.max(...fps) : NaN,
    shFps: live.length ? Math.min(...live.map((c) => c.frames["/depthao/shaded"] / secs)) : NaN,
    shFpsMax: live.length ? Math.max(...live.map((c) => c.frames["/depthao/shaded"] / secs)) : NaN,
    frames: live.map((c) => c.frames["/depthao/ao"] + c.frames["/depthao/shaded"]),
    stalledFrames: clients.filter((c) => c.stalled).map((c) => c.frames["/depthao/ao"] + c.frames["/depthao/shaded"]),
    med: quantile(lat, 0.5), p95: quantile(lat, 0.95),
    sockMed: m ? Number(m[1]) : NaN, sockP99: m ? Number(m[2]) : NaN,
    dropped: dropped ? Number(dropped[1]) : NaN,
    inSink: inSink ? Number(inSink[1]) : NaN, build: inSink ? Number(inSink[2]) : NaN,
    sinkCpu: (c1.sink - c0.sink) / secs, lwsCpu: (c1.lws - c0.lws) / secs, allCpu: (c1.all - c0.all) / secs,
  };
}

function f(x, d = 1) {
  return Number.isFinite(x) ? x.toFixed(d) : "-";
}

async function main() {
  const a = parseArgs(process.argv.slice(2));
  const load0 = os.loadavg();
  console.log(`fox-load: ${os.cpus().length} CPUs, load average ${load0.map((x) => x.toFixed(2)).join(" ")} at the start; ` +
    `${a.seconds} s per round after ${a.warmup} s warm-up; channels /depthao/ao (RawImage mono16) + /depthao/shaded (jpeg)` +
    (a.stall ? "; the last client of each round of 2 or more stalled (not counted in fps/latency)" : ""));
  console.log("| clients | AO fps per client (min-max) | shaded fps per client (min-max) | latency capture->receipt median | p95 | " +
    "sink capture->socket median (p99) | of it in the sink (building) | dropped | sink threads CPU (of it fox:lws) | daemon CPU |");
  console.log("|---|---|---|---|---|---|---|---|---|---|");
  const rows = [];
  for (const n of a.clients) {
    const r = await round(a, n);
    rows.push(r);
    console.log(`| ${n}${r.stall ? " (1 stalled)" : ""} | ${f(r.aoFps)}-${f(r.aoFpsMax)} | ${f(r.shFps)}-${f(r.shFpsMax)} | ` +
      `${f(r.med)} ms | ${f(r.p95)} ms | ${f(r.sockMed)} (${f(r.sockP99)}) ms | ${f(r.inSink)} (${f(r.build)}) ms | ${f(r.dropped, 0)} | ` +
      `${f(r.sinkCpu * 100)} % (${f(r.lwsCpu * 100)} %) | ${f(r.allCpu * 100)} % |`);
  }
  const base = rows.find((r) => r.n === 0);
  const more = rows.filter((r) => r.n > 1);
  if (base && more.length) {
    const one = rows.find((r) => r.n === 1);
    const last = more[more.length - 1];
    const per = one ? (last.sinkCpu - one.sinkCpu) / (last.n - one.n) : NaN;
    console.log(`sink CPU: ${f(base.sinkCpu * 100, 2)} % of a core with 0 clients` +
      (one ? `, ${f(one.sinkCpu * 100, 2)} % with 1, ${f(per * 100, 2)} % per further client (1 -> ${last.n})` : ""));
  }
  console.log(`load average ${os.loadavg().map((x) => x.toFixed(2)).join(" ")} at the end`);
}

main().catch((e) => t.fail(e.stack || String(e)));
