// The end-to-end test's harness: the page helpers every checks file uses (the app's status
// element, waiting for a state, clicks and drags on published rectangles, pixels of a
// screenshot), the check/report bookkeeping, and the frame-gap recordings. The checks
// themselves are in e2e/checks/, one file per tab; e2e/e2e.mjs runs them.
//
// Nothing here asserts a time: a wait is for a state of the app (its status JSON, the
// page's address, local storage, pixels on screen), and its timeout is a hang guard only,
// generous for a loaded 2-core machine. Frame gaps are recorded and reported, not asserted.
import { PNG } from "pngjs";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

export const here = path.dirname(fileURLToPath(import.meta.url));
export const repo = path.join(here, "..");
export const examples = path.join(repo, "examples");
export const artifacts = path.join(here, "artifacts");
fs.mkdirSync(artifacts, { recursive: true });

/// How long a wait for a state may last before the app is called stuck (ms): a hang guard.
export const HANG_GUARD_MS = 180000;

/// A file of the repository as text, and an example scene as parsed JSON.
export const readText = (...parts) => fs.readFileSync(path.join(repo, ...parts), "utf8");
export const example = (name) => JSON.parse(readText("examples", name));
export const shotPath = (name) => path.join(artifacts, name);

// ---- check and report ----

export const results = [];
/// Records one assertion and prints it (`ok` or `FAIL`, its name, what was measured).
export function check(name, ok, detail = "") {
  results.push({ name, ok: Boolean(ok) });
  console.log(`${ok ? "ok  " : "FAIL"}  ${name}${detail ? " — " + detail : ""}`);
}

// The machine's load (frame times on a shared CPU depend on it).
export const loadAverage = () => os.loadavg().map((x) => Math.round(x * 100) / 100);

export function base64url(text) {
  return Buffer.from(text, "utf8").toString("base64").replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

// ---- the app's status element ----

/// The app's status JSON (`#app-status`, written by the app at the end of every frame).
export async function status(page) {
  const text = await page.locator("#app-status").textContent();
  return text ? JSON.parse(text) : null;
}

/// Polls the status until `pred` holds; throws after `timeoutMs` (a hang guard).
export async function waitFor(page, what, pred, timeoutMs = HANG_GUARD_MS) {
  const t0 = Date.now();
  let last = null;
  while (Date.now() - t0 < timeoutMs) {
    last = await status(page).catch(() => null);
    if (last && pred(last)) return last;
    await page.waitForTimeout(100);
  }
  throw new Error(`timed out waiting for ${what}; last status: ${JSON.stringify(last)}`);
}

/// Polls something other than the status (the address, local storage) until it holds.
export async function waitUntil(page, what, probe, timeoutMs = HANG_GUARD_MS) {
  const t0 = Date.now();
  let last;
  while (Date.now() - t0 < timeoutMs) {
    last = await probe();
    if (last) return last;
    await page.waitForTimeout(100);
  }
  throw new Error(`timed out waiting for ${what}`);
}

/// The crease has been computed and the app has drawn a few frames.
export const settled = (s) => s.frames >= 3 && !s.running && s.periods >= 0 && s.stop !== null;

/// A tab's panel has finished computing.
export const panelDone = (title) => (s) => s.panel && s.panel.title === title && s.panel.status && s.panel.status.computing === false;

/// Opens a new page at `address` and waits until its crease is computed.
export async function openSettled(context, address, what = "the app") {
  const page = await context.newPage();
  await page.goto(address);
  const s = await waitFor(page, what, settled);
  return { page, s };
}

// ---- input on published rectangles [x, y, w, h] ----

export async function clickRect(page, r) {
  await page.mouse.click(r[0] + r[2] / 2, r[1] + r[3] / 2);
}

/// Drags a slider by its published rectangle from `from` to `to` points along its rail, in
/// small steps as a hand would.
export async function dragSlider(page, r, from = 40, to = 70, steps = 10) {
  await page.mouse.move(r[0] + from, r[1] + r[3] / 2);
  await page.mouse.down();
  await page.mouse.move(r[0] + to, r[1] + r[3] / 2, { steps });
  await page.mouse.up();
}

/// Clicks the widget the status publishes under `rectOf(status)` until `pred` holds. The
/// layout can move (a banner comes and goes), so a rectangle may be a frame old: if the app
/// has drawn `frames` frames since the click and `pred` still fails, the click missed and is
/// made again from the rectangle as it is now. Waits for frames, not for a time.
export async function clickUntil(page, what, rectOf, pred, { tries = 5, frames = 10 } = {}) {
  for (let i = 0; i < tries; i++) {
    const before = await status(page);
    const r = rectOf(before);
    if (r) await clickRect(page, r);
    const s = await waitFor(page, what, (s) => pred(s) || s.frames >= before.frames + frames);
    if (pred(s)) return s;
  }
  throw new Error(`clicking did not give ${what}`);
}

// ---- pixels ----

/// Distinct colours (5 bits a channel) in a region of a screenshot: a blank canvas has one.
export function colourVariety(pngBuffer, region) {
  const png = PNG.sync.read(pngBuffer);
  const seen = new Set();
  const [x0, y0, w, h] = region.map(Math.round);
  for (let y = y0; y < y0 + h; y += 2) {
    for (let x = x0; x < x0 + w; x += 2) {
      const i = (png.width * y + x) << 2;
      seen.add((png.data[i] >> 3) << 10 | (png.data[i + 1] >> 3) << 5 | (png.data[i + 2] >> 3));
    }
  }
  return seen.size;
}

/// The main view's region in the 1400×900 window.
export const VIEW = [420, 60, 900, 520];

/// Takes screenshots until `measure(png)` passes `ok` (what the status reported is on
/// screen), or the hang guard ends; saves the last one as `file` and returns it with its
/// measure. The caller asserts on the measure.
export async function screenshotUntil(page, file, measure, ok, timeoutMs = 60000) {
  const t0 = Date.now();
  for (;;) {
    const shot = await page.screenshot({ path: file ? shotPath(file) : undefined });
    const value = measure(shot);
    if (ok(value) || Date.now() - t0 > timeoutMs) return { shot, value };
    await page.waitForTimeout(250);
  }
}

/// A screenshot once `region` shows more than `min` colours (the view is drawn), saved as
/// `file`; returns the count seen.
export async function drawnVariety(page, file, region, min) {
  const { value } = await screenshotUntil(page, file, (shot) => colourVariety(shot, region), (v) => v > min);
  return value;
}

// ---- frame gaps (recorded by e2e/browser.mjs on every page), measured, never asserted ----

export const frameReport = [];
export async function resetFrames(page) {
  await page.evaluate(() => { window.__frameGaps.length = 0; });
}
export async function recordFrames(page, label, tab) {
  const gaps = await page.evaluate(() => window.__frameGaps.splice(0));
  if (gaps.length === 0) return;
  const sorted = [...gaps].sort((a, b) => a - b);
  const q = (f) => sorted[Math.min(sorted.length - 1, Math.floor(f * sorted.length))];
  const row = { label, tab, frames: gaps.length, median_ms: q(0.5), p99_ms: q(0.99), longest_ms: sorted[sorted.length - 1] };
  frameReport.push(row);
  console.log(`      frames while ${label}: ${row.frames}, median ${row.median_ms.toFixed(1)} ms, p99 ${row.p99_ms.toFixed(1)} ms, longest ${row.longest_ms.toFixed(1)} ms`);
}

/// Per tab, the worst of its recordings (median and p99 of the recording with the highest
/// p99), printed and written with the load average to e2e/artifacts/frames.json.
export function writeFrameReport(loadAtStart) {
  if (frameReport.length === 0) return;
  const tabs = {};
  for (const r of frameReport) {
    const t = tabs[r.tab] ?? { frames: 0, median_ms: 0, p99_ms: 0, longest_ms: 0 };
    t.frames += r.frames;
    t.median_ms = Math.max(t.median_ms, r.median_ms);
    t.p99_ms = Math.max(t.p99_ms, r.p99_ms);
    t.longest_ms = Math.max(t.longest_ms, r.longest_ms);
    tabs[r.tab] = t;
  }
  for (const [t, v] of Object.entries(tabs)) {
    console.log(`      tab ${t}: ${v.frames} frames, median ≤ ${v.median_ms.toFixed(1)} ms, p99 ≤ ${v.p99_ms.toFixed(1)} ms, longest ${v.longest_ms.toFixed(1)} ms`);
  }
  const load = { start: loadAtStart, end: loadAverage() };
  fs.writeFileSync(path.join(artifacts, "frames.json"), JSON.stringify({ load_average: load, recordings: frameReport, tabs }, null, 2));
  console.log(`      load average (1, 5, 15 min) at the start ${load.start.join(", ")}, at the end ${load.end.join(", ")}`);
  const longest = frameReport.reduce((a, b) => (b.longest_ms > a.longest_ms ? b : a));
  console.log(`\nlongest frame: ${longest.longest_ms.toFixed(1)} ms (${longest.label}); all in e2e/artifacts/frames.json`);
}
