// SPDX-License-Identifier: MIT
// SIGTERM with clients attached — subscribed, and one that stopped reading — ends
// depthaod in under a second (the requirement), with exit status 0.
// usage: node test_fox_stop.js DEPTHAOD PLUGIN_DIRS
"use strict";
const t = require("./foxtest.js");

async function main() {
  const [depthaod, plugins] = process.argv.slice(2);
  const d = new t.Daemon(depthaod, plugins, "control=true");
  const port = await d.ready();
  const clients = [];
  for (let i = 0; i < 4; i++) {
    const c = await t.connect(port);
    for (const ch of c.channels) c.client.subscribe(ch.id);
    clients.push(c);
  }
  let n = 0;
  clients[0].client.on("message", () => n++);
  await t.sleep(1500);
  clients[3].ws._socket.pause(); // stalled: the kernel buffers fill, lws holds the rest
  await t.sleep(1500);
  if (!n) t.fail("no messages before the stop");
  const secs = await d.stop();
  console.log(`stopped in ${secs.toFixed(3)} s with ${clients.length} clients attached (exit ${d.exited.code})`);
  if (d.exited.code !== 0) t.fail("exit status " + d.exited.code + ": " + d.text());
  if (secs >= 1.0) t.fail(`SIGTERM took ${secs.toFixed(3)} s (1 s at most)`);
  const line = /foxglove: .* clients served.*/.exec(d.text());
  if (!line) t.fail("no closing line from the sink: " + d.text());
  console.log(line[0]);
  process.exit(0);
}

main().catch((e) => t.fail(e.stack || String(e)));
