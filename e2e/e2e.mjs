// End-to-end test of the release web app in Debian's headless Chromium (driven by
// playwright-core; no browser download), as a new user would meet it:
//
//   node e2e/e2e.mjs http://127.0.0.1:PORT/ [--only crease,files,…]
//
// The checks are in e2e/checks/, one file per tab (crease, files: open / save / share /
// reload, fiveaxis, chords, nurbs, simulate, fillet, webgpu), each a list of named checks;
// e2e/harness.mjs has the page helpers. Each named check runs on its own; one that throws
// (a state never reached) is reported with its name and the rest still run. Then: no
// console error on any page, WebGPU in a browser of its own, and the frame gaps per tab
// (e2e/artifacts/frames.json, reported, not asserted). Screenshots go to e2e/artifacts/.
import { openBrowser } from "./browser.mjs";
import { check, loadAverage, results, writeFrameReport } from "./harness.mjs";
import * as crease from "./checks/crease.mjs";
import * as files from "./checks/files.mjs";
import * as fiveaxis from "./checks/fiveaxis.mjs";
import * as chords from "./checks/chords.mjs";
import * as nurbs from "./checks/nurbs.mjs";
import * as simulate from "./checks/simulate.mjs";
import * as fillet from "./checks/fillet.mjs";
import * as webgpu from "./checks/webgpu.mjs";

const args = process.argv.slice(2);
const url = args.find((a) => a.startsWith("http")) ?? "http://127.0.0.1:8765/";
const onlyArg = args.includes("--only") ? args[args.indexOf("--only") + 1] : null;
const only = onlyArg ? new Set(onlyArg.split(",")) : null;

// In this order: the tabs in one browser (WebGL2 on SwiftShader, wgpu's fallback), then
// WebGPU in a browser of its own.
const tabs = { crease, files, fiveaxis, chords, nurbs, simulate, fillet };
const loadAtStart = loadAverage();
let thrown = 0;

async function runChecks(group, list, env) {
  for (const { name, run } of list) {
    try {
      await run(env);
    } catch (e) {
      thrown += 1;
      console.log(`FAIL  ${group}: ${name} — ${e.message}`);
    }
  }
}

const { browser, context } = await openBrowser();
const consoleErrors = [];
context.on("console", (m) => { if (m.type() === "error") consoleErrors.push(m.text()); });
context.on("weberror", (e) => consoleErrors.push(String(e.error())));
for (const [group, mod] of Object.entries(tabs)) {
  if (only && !only.has(group)) continue;
  // Each file's checks share a `state` (a page one check leaves for the next).
  await runChecks(group, mod.checks, { context, url, state: {} });
}
const unexpected = consoleErrors.filter((t) => !/GPU stall due to ReadPixels/.test(t));
check("no console error", unexpected.length === 0, unexpected.slice(0, 5).join(" | "));
await browser.close();

if (!only || only.has("webgpu")) await runChecks("webgpu", webgpu.checks, { url, state: {} });

writeFrameReport(loadAtStart);
const passed = results.filter((r) => r.ok).length;
const failedCount = results.length - passed + thrown;
console.log(`\ne2e: ${passed} passed, ${failedCount} failed (screenshots in e2e/artifacts/)`);
process.exit(failedCount === 0 ? 0 : 1);
