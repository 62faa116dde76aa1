// SPDX-License-Identifier: MIT
// Bundles tools/foxview (esbuild from tests/js), opens it in Debian's chromium,
// headless, against a running Foxglove WebSocket server, waits until every panel
// shows live data and saves a screenshot.  Also a module for the test
// (tests/foxglove/test_fox_view.js): the page's state through the DevTools protocol.
//
//   node tools/foxview/shot.js PORT OUT.png
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");
const { spawn } = require("child_process");

const root = path.join(__dirname, "..", "..");
const modules = path.join(root, "tests", "js", "node_modules");

// The chromium binary, or null.
function chromium() {
  for (const p of [process.env.CHROMIUM, "/usr/bin/chromium", "/usr/bin/chromium-browser"])
    if (p && fs.existsSync(p)) return p;
  return null;
}

// The page and its bundle in a fresh directory; returns index.html's path.
function build() {
  const esbuild = require(path.join(modules, "esbuild"));
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "foxview-"));
  esbuild.buildSync({ entryPoints: [path.join(__dirname, "view.js")], bundle: true,
    outfile: path.join(dir, "bundle.js"), nodePaths: [modules], platform: "browser",
    logLevel: "error" });
  fs.copyFileSync(path.join(__dirname, "index.html"), path.join(dir, "index.html"));
  return path.join(dir, "index.html");
}

// A headless chromium on the page; resolves with { eval(expr), shot(file), close() }.
async function open(port, opts = {}) {
  const WebSocket = require(path.join(modules, "ws"));
  const page = build();
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "foxview-profile-"));
  const proc = spawn(chromium(), ["--headless", "--no-sandbox", "--disable-gpu",
    "--remote-debugging-port=0", `--user-data-dir=${profile}`, "--window-size=1150,920",
    "--hide-scrollbars", `file://${page}?port=${port}`], { stdio: ["ignore", "ignore", "pipe"] });
  let errText = "";
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error("chromium did not start: " + errText)), 60000);
    proc.stderr.on("data", (b) => {
      errText += b;
      const m = /DevTools listening on (ws:\S+)/.exec(errText);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    proc.on("exit", () => reject(new Error("chromium exited: " + errText)));
  });
  const dport = new URL(url).port;
  const list = await (await fetch(`http://127.0.0.1:${dport}/json/list`)).json();
  const target = list.find((t) => t.type === "page");
  const ws = new WebSocket(target.webSocketDebuggerUrl, { maxPayload: 512 << 20 });
  await new Promise((r, j) => { ws.on("open", r); ws.on("error", j); });
  let id = 0;
  const waiting = new Map();
  ws.on("message", (b) => {
    const m = JSON.parse(b);
    if (m.id && waiting.has(m.id)) { waiting.get(m.id)(m); waiting.delete(m.id); }
  });
  const call = (method, params = {}) => new Promise((resolve, reject) => {
    const n = ++id;
    waiting.set(n, (m) => (m.error ? reject(new Error(method + ": " + m.error.message)) : resolve(m.result)));
    ws.send(JSON.stringify({ id: n, method, params }));
  });
  const evaluate = async (expr) => {
    const r = await call("Runtime.evaluate", { expression: expr, returnByValue: true, awaitPromise: true });
    if (r.exceptionDetails) throw new Error(expr + ": " + JSON.stringify(r.exceptionDetails));
    return r.result.value;
  };
  await call("Emulation.setDeviceMetricsOverride", { width: 1150, height: 960, deviceScaleFactor: 1,
    mobile: false });
  return {
    evaluate,
    async live(timeoutMs = opts.timeoutMs || 60000) {
      const until = Date.now() + timeoutMs;
      for (;;) {
        const s = await evaluate("window.foxview ? window.foxview.status : 'loading'");
        if (s === "live") return;
        if (Date.now() > until) {
          const st = await evaluate("JSON.stringify(window.foxview || null)");
          throw new Error(`the page did not show every panel in ${timeoutMs} ms: ${st}`);
        }
        await new Promise((r) => setTimeout(r, 200));
      }
    },
    async shot(file) {
      const r = await call("Page.captureScreenshot", { format: "png" });
      fs.writeFileSync(file, Buffer.from(r.data, "base64"));
    },
    async close() {
      ws.close();
      const done = new Promise((r) => proc.on("exit", r));
      proc.kill("SIGTERM");
      const k = setTimeout(() => proc.kill("SIGKILL"), 5000);
      await done;
      clearTimeout(k);
      // chromium's helper processes may still write into the profile after the main
      // process has gone: retry, and a directory left behind is a warning, not a failure
      for (const dir of [profile, path.dirname(page)]) {
        try {
          fs.rmSync(dir, { recursive: true, force: true, maxRetries: 20, retryDelay: 100 });
        } catch (e) {
          console.error(`warning: could not remove ${dir}: ${e.message}`);
        }
      }
    },
  };
}

module.exports = { chromium, open };

if (require.main === module) {
  (async () => {
    const [port, out] = process.argv.slice(2);
    if (!port || !out) {
      console.error("usage: node tools/foxview/shot.js PORT OUT.png (depthaod with --sink fox=foxglove:PORT running)");
      process.exit(2);
    }
    if (!chromium()) {
      console.error("foxview: chromium is not installed (apt-get install chromium)");
      process.exit(1);
    }
    const v = await open(port);
    try {
      await v.live();
      await new Promise((r) => setTimeout(r, 1500)); /* a few frames more on every panel */
      await v.shot(out);
      console.log(`foxview: ${out}`);
    } finally {
      await v.close();
    }
  })().catch((e) => { console.error("foxview: " + (e.stack || e)); process.exit(1); });
}
