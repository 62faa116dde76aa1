// SPDX-License-Identifier: MIT
// Ten reference clients at once on the shaded JPEG channel, one of them stalled
// (subscribed to every channel, then never reading): each of the nine others
// receives at least 90 % of the frames published meanwhile, and the stalled one
// has its oldest messages dropped.  Measured (printed, not asserted): the
// daemon's CPU time with 1 and with 10 clients, hence per extra client, and the
// sink's median latency capture -> the message's last byte to the socket.
// usage: node test_fox_clients.js DEPTHAOD PLUGIN_DIRS
"use strict";
const fs = require("fs");
const t = require("./foxtest.js");

function cpuSeconds(pid) {
  const f = fs.readFileSync(`/proc/${pid}/stat`, "utf8").split(") ")[1].split(" ");
  return (Number(f[11]) + Number(f[12])) / 100; // utime + stime, clock ticks of 10 ms
}

async function watch(port) {
  const c = await t.connect(port);
  const ch = c.channels.find((x) => x.topic === "/depthao/shaded");
  c.client.subscribe(ch.id);
  c.seen = new Set();
  c.client.on("message", (m) => c.seen.add(String(m.timestamp)));
  return c;
}

async function cpuOver(d, ms) {
  const c0 = cpuSeconds(d.proc.pid);
  await t.sleep(ms);
  return cpuSeconds(d.proc.pid) - c0;
}

async function main() {
  const [depthaod, plugins] = process.argv.slice(2);
  const d = new t.Daemon(depthaod, plugins, "max-clients=16");
  const port = await d.ready();
  const first = await watch(port);
  await t.sleep(1000);
  const cpu1 = await cpuOver(d, 4000);
  const clients = [first];
  for (let i = 1; i < 9; i++) clients.push(await watch(port));
  const stalled = await t.connect(port);
  for (const ch of stalled.channels) stalled.client.subscribe(ch.id);
  await t.sleep(500);
  stalled.ws._socket.pause();
  await t.sleep(1000);
  for (const c of clients) c.seen.clear();
  const cpu10 = await cpuOver(d, 5000);
  const counts = clients.map((c) => c.seen.size);
  const all = new Set();
  for (const c of clients) for (const s of c.seen) all.add(s);
  const secs = await d.stop();
  const line = /foxglove: .* clients served.*/.exec(d.text());
  console.log(`published ${all.size} frames in 5 s (${(all.size / 5).toFixed(1)} fps); the 9 reading clients got ${counts.join(" ")}`);
  console.log(`daemon CPU: ${(cpu1 / 4).toFixed(3)} s/s with 1 client, ${(cpu10 / 5).toFixed(3)} s/s with 10 (one stalled): ` +
    `${((cpu10 / 5 - cpu1 / 4) / 9 * 1000).toFixed(1)} ms of CPU a second per extra client`);
  console.log(line ? line[0] : "no closing line", `; stopped in ${secs.toFixed(3)} s`);
  if (all.size < 30) t.fail("fewer than 30 frames published in 5 s");
  for (const n of counts) if (n < 0.9 * all.size) t.fail(`a reading client got ${n} of ${all.size} frames`);
  const dropped = line && /(\d+) dropped/.exec(line[0]);
  if (!dropped || Number(dropped[1]) === 0) t.fail("the stalled client had nothing dropped");
  process.exit(0);
}

main().catch((e) => t.fail(e.stack || String(e)));
