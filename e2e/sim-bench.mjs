// Measures the cutting simulation's benchmark in the release web app in headless Chromium
// (SwiftShader, 1400×900): the native benchmark's 10 000-move 5-axis program
// (`interpolab::simulate::bench`, the same moves as benches/simulate.rs) on its 512 × 512
// grid, built and machined in the simulation tab's Web Worker. Not a test: it measures and
// reports, and asserts nothing.
//
//   node e2e/sim-bench.mjs http://127.0.0.1:PORT/ [--moves 10000] [--pitch 0.1] [--runs 2] [--replays 4]
//     [--hide view3d] [--worker-only N] [--trace FILE] [--press MS] [--block-worker]
//     [--first-frame N]
//
// The program reaches the tab through the page address (`?view=Cutting+simulation&set=
// benchmark:five-axis:N`, `app::query_options`): the worker builds it from those few
// numbers, so no 10 000-line G-code text crosses to the page. Per run: the wall time from
// the run's start to done (the app's `sim_ms`: the job's start, the worker's start, the
// program built, machined, measured, the output decoded), the machining phase as the page
// sees it (progress 0.1 → 0.9, polled every 25 ms), ray updates per second over each, the
// longest frame meanwhile (animation-frame gaps) and the longest time a frame spent on the
// job (`slowest_frame_ms`), and the progress values the page showed. Then (--replays) the
// move slider: `set_option("move", k)` through the address is not available after the
// start, so replays are timed by dragging the published slider rectangle, from release to
// the exact stock at the move (stage done, `moves_simulated` the slider's move).
// Writes e2e/artifacts/sim-bench.json and a screenshot e2e/artifacts/sim-bench.png.
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { openBrowser } from "./browser.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const url = args.find((a) => a.startsWith("http")) ?? "http://127.0.0.1:8765/";
const arg = (name, dflt) => (args.includes(name) ? args[args.indexOf(name) + 1] : dflt);
const moves = Number(arg("--moves", "10000"));
const pitch = arg("--pitch", "0.1");
const runs = Number(arg("--runs", "2"));
const replays = Number(arg("--replays", "4"));
// --trace FILE: a Chromium trace (main thread, worker, GPU process) of each run (FILE, then
// FILE-2.json, …), for finding what a long frame did (open it in chrome://tracing or Perfetto).
const traceFile = arg("--trace", null);
// --worker-only N: after the app's runs, the same request the app posted to its worker (the
// first `simulate-run` message recorded on the page) is run N times in a bare Web Worker of
// the same build on a page that draws nothing (the build's assets/manifest.json): the
// worker's compute-only time in this Chromium, for comparing with the app's `sim_ms` (which
// adds the page's frames competing for the cores, decoding the partials and the output).
const workerOnly = Number(arg("--worker-only", "0"));
// --js-flags FLAGS: the --worker-only runs in a second Chromium started with these V8 flags
// (e.g. `--no-liftoff`: the wasm compiled by the optimising tier at once), to see what the
// engine's tiers cost the worker.
const jsFlags = arg("--js-flags", null);
// --hide LIST: passed as the page's `hide=` (app/ablate.rs), e.g. `view3d` to leave the 3D
// view's drawing out of every frame (a measurement of the run without the stock's frames).
const hide = arg("--hide", null);
// --press MS: the user on an already open page instead of an address that starts the run:
// the tab opened with no program to run (`set=source:loaded` with no file loaded, the
// benchmark's pitch), left idle MS ms after its first frame, then the benchmark chosen from
// the tab's program menu with the mouse (the same request as the address's). `sim_ms` is
// then from the choice's frame; `pressed_ms` is the click.
const press = args.includes("--press") ? Number(arg("--press", "2000")) : null;
// --block-worker: the worker's script is refused (HTTP 404) on the app's pages, so no
// worker can start (neither the one the page starts while it loads nor a job's own): shows
// the fallback (the job runs on the page, `in_background` false) and what it costs.
const blockWorker = args.includes("--block-worker");
const artifacts = path.join(here, "artifacts");
fs.mkdirSync(artifacts, { recursive: true });

// --first-frame N: only the page's first frame, no run: the default page (no address options)
// opened in N fresh browsers one after another (no HTTP cache), each's `first_frame_ms` and
// its workers' timeline (the spare worker starts after the first frame), then exit. Run it
// against two builds in turn to compare their first frames.
const firstFrames = Number(arg("--first-frame", "0"));
if (firstFrames > 0) {
  const rows = [];
  for (let i = 0; i < firstFrames; i++) {
    const { browser: b, context: c } = await openBrowser();
    await c.addInitScript(() => {
      window.__workers = [];
      const Base = window.Worker;
      window.Worker = class extends Base {
        constructor(...a) {
          super(...a);
          const rec = { created: Math.round(performance.now()) };
          window.__workers.push(rec);
          this.addEventListener("message", (e) => {
            if (rec.ready === undefined && String(e.data).startsWith("ready\n")) rec.ready = Math.round(performance.now());
          });
        }
      };
    });
    const p = await c.newPage();
    await p.goto(url);
    await p.waitForFunction(() => {
      const t = document.getElementById("app-status")?.textContent;
      try { return t && JSON.parse(t).first_frame_ms != null; } catch { return false; }
    }, null, { timeout: 60000 });
    await p.waitForTimeout(1500);
    const row = await p.evaluate(() => ({
      first_frame_ms: Math.round(JSON.parse(document.getElementById("app-status").textContent).first_frame_ms),
      workers: window.__workers,
    }));
    row.load = os.loadavg().map((x) => Math.round(x * 100) / 100);
    rows.push(row);
    console.log(`first frame: ${JSON.stringify(row)}`);
    await b.close();
  }
  const ff = rows.map((r) => r.first_frame_ms).sort((x, y) => x - y);
  console.log(`first frames (ms): ${ff.join(", ")}; median ${ff[Math.floor(ff.length / 2)]}`);
  fs.writeFileSync(path.join(artifacts, "sim-bench-first-frame.json"), JSON.stringify(rows, null, 2));
  process.exit(0);
}

const { browser, context } = await openBrowser();
const errors = [];
context.on("console", (m) => { if (m.type() === "error" || m.type() === "warning") errors.push(m.text()); });

async function status(page) {
  const text = await page.locator("#app-status").textContent().catch(() => null);
  try { return text ? JSON.parse(text) : null; } catch { return null; }
}

const sim = (s) => s && s.panel && s.panel.title === "Cutting simulation" ? s.panel.status : null;
const load = () => os.loadavg().map((x) => Math.round(x * 100) / 100);
const report = { moves, pitch_mm: Number(pitch), hide, press_idle_ms: press, block_worker: blockWorker, load_at_start: load(), runs: [], replays: [], worker_only: [] };

// Records what the page posts to its workers (the job requests), for --worker-only, and a
// timeline of every worker (ms since navigation, the page's `performance.now()`): created,
// said ready, the simulation's request posted, its first progress and partial output, the
// machining's start and end (progress 0.1 and 0.9), its answer; and the page's own wasm
// (`TrunkApplicationStarted`: the app's module fetched, compiled and started).
await context.addInitScript(() => {
  window.__workerPosts = [];
  window.__workers = [];
  window.__appStarted = null;
  addEventListener("TrunkApplicationStarted", () => { window.__appStarted = performance.now(); });
  const at = () => Math.round(performance.now());
  const Base = window.Worker;
  window.Worker = class extends Base {
    constructor(...a) {
      super(...a);
      const rec = { created: at() };
      window.__workers.push(rec);
      this.__rec = rec;
      this.addEventListener("message", (e) => {
        const text = typeof e.data === "string" ? e.data : "";
        const tag = text.slice(0, text.indexOf("\n"));
        if (tag === "ready" && rec.ready === undefined) rec.ready = at();
        if (rec.posted === undefined) return;
        if (tag === "progress") {
          const f = Number(text.slice(9));
          if (rec.first_progress === undefined) rec.first_progress = at();
          if (f >= 0.1 && rec.machining_from === undefined) rec.machining_from = at();
          if (f >= 0.9 && rec.machining_to === undefined) rec.machining_to = at();
        } else if (tag === "partial" && rec.first_partial === undefined) rec.first_partial = at();
        else if ((tag === "ok" || tag === "err") && rec.answer === undefined) { rec.answer = at(); rec.answer_chars = text.length; }
      });
    }
  };
  const post = Base.prototype.postMessage;
  Base.prototype.postMessage = function (m, ...rest) {
    if (typeof m === "string" && m.startsWith("simulate-run\n")) {
      if (window.__workerPosts.length < 4) window.__workerPosts.push(m);
      if (this.__rec && this.__rec.posted === undefined) { this.__rec.posted = at(); this.__rec.request_chars = m.length; }
    }
    return post.call(this, m, ...rest);
  };
});

const query = press === null
  ? `?view=${encodeURIComponent("Cutting simulation")}&set=${encodeURIComponent(`benchmark:five-axis:${moves}`)}`
    + (pitch === "0.1" ? "" : `&set=${encodeURIComponent(`pitch:${pitch}`)}`)
    + (hide ? `&hide=${encodeURIComponent(hide)}` : "")
  // --press: the tab with no program to run (no G-code file loaded) and the benchmark's pitch;
  // the benchmark is then chosen from the tab's program menu.
  : `?view=${encodeURIComponent("Cutting simulation")}&set=source:loaded&set=${encodeURIComponent(`pitch:${pitch}`)}`
    + (hide ? `&hide=${encodeURIComponent(hide)}` : "");

// Chooses the benchmark from the tab's program menu with the mouse, as a user would: opens
// the menu (its published rectangle `sim_source`), then clicks the benchmark's item (its
// published rectangle `sim_source_benchmark` once the menu is open; builds that do not
// publish it: the last of the menu's seven items, found from the menu button's height).
// Returns the page's `performance.now()` at the click.
async function chooseBenchmark(page) {
  const ui = (await status(page))?.panel?.status?.ui ?? {};
  const combo = ui.sim_source;
  if (!combo) throw new Error("the program menu's rectangle (sim_source) is not published");
  await page.mouse.click(combo[0] + combo[2] / 2, combo[1] + combo[3] / 2);
  let item = null;
  for (let i = 0; i < 40 && !item; i++) {
    await page.waitForTimeout(25);
    item = (await status(page))?.panel?.status?.ui?.sim_source_benchmark ?? null;
  }
  const [x, y] = item
    ? [item[0] + item[2] / 2, item[1] + item[3] / 2]
    : [combo[0] + combo[2] / 2, combo[1] + combo[3] + 6 + 6.5 * (combo[3] + 2)];
  const clicked = await page.evaluate(() => performance.now());
  await page.mouse.click(x, y);
  return { clicked, item_published: item !== null };
}
let posted = null;
let page = null;
for (let r = 0; r < runs; r++) {
  page = await context.newPage();
  if (blockWorker) await page.route(/\/(jobs-worker|interpolab-worker_loader)\.js$/, (r) => r.fulfill({ status: 404, body: "blocked by sim-bench" }));
  if (traceFile) {
    await browser.startTracing(page, {
      path: r === 0 ? traceFile : traceFile.replace(/(\.json)?$/, `-${r + 1}.json`),
      categories: ["devtools.timeline", "disabled-by-default-devtools.timeline", "v8", "v8.execute", "disabled-by-default-v8.cpu_profiler",
        "disabled-by-default-v8.gc", "blink", "gpu", "toplevel", "disabled-by-default-devtools.timeline.frame"],
    });
  }
  let t0 = Date.now();
  await page.goto(url + query);
  let pressed = null;
  if (press !== null) {
    // An open page, idle: then the run through the tab's menu.
    await page.waitForFunction(() => {
      const t = document.getElementById("app-status")?.textContent;
      try { return t && JSON.parse(t).first_frame_ms != null; } catch { return false; }
    }, null, { timeout: 60000 });
    await page.waitForTimeout(press);
    pressed = await chooseBenchmark(page);
    t0 = Date.now();
  }
  const progress = [];
  let seenRun = null;
  let machStart = null;
  let machEnd = null;
  let st = null;
  while (Date.now() - t0 < 600000) {
    const s = sim(await status(page));
    const now = Date.now();
    if (s) {
      if (s.computing && seenRun === null) {
        seenRun = now;
        await page.evaluate(() => { window.__frameGaps.length = 0; });
      }
      if (s.computing && (progress.length === 0 || progress[progress.length - 1][1] !== s.progress)) {
        progress.push([now - (seenRun ?? now), s.progress]);
      }
      if (machStart === null && s.progress >= 0.1 && s.computing) machStart = now;
      if (machEnd === null && (s.progress >= 0.9 || s.stage === "done")) machEnd = now;
      if ((s.stage === "done" || s.stage === "error") && (press === null || s.source === "benchmark")) { st = s; break; }
    }
    await page.waitForTimeout(25);
  }
  const doneAt = await page.evaluate(() => performance.now());
  const gaps = await page.evaluate(() => window.__frameGaps.splice(0));
  const whole = await status(page);
  const timeline = await page.evaluate(() => ({ app_started: window.__appStarted && Math.round(window.__appStarted), workers: window.__workers }));
  if (posted === null) posted = await page.evaluate(() => window.__workerPosts[0] ?? null);
  const sorted = [...gaps].sort((a, b) => a - b);
  const q = (f) => sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(f * sorted.length))] : null;
  const row = {
    stage: st && st.stage, error: st && st.error, grid: st && st.grid, moves: st && st.moves_simulated,
    ray_updates: st && st.ray_updates, removed_volume_mm3: st && st.removed_volume_mm3,
    in_background: st && st.in_background,
    sim_ms: st && st.sim_ms,
    seen_ms: seenRun === null ? null : Date.now() - seenRun,
    machining_seen_ms: machStart !== null && machEnd !== null ? machEnd - machStart : null,
    frames: gaps.length, frame_median_ms: q(0.5), frame_p99_ms: q(0.99), frame_longest_ms: q(1),
    slowest_frame_ms: st && st.slowest_frame_ms,
    progress_values: progress.length, progress_first: progress.slice(0, 3), progress_last: progress.slice(-3),
    // ms since navigation: the page's wasm started, its first frame, the done seen (polled
    // every 25 ms; it comes after the frame that decoded the output and drew the result),
    // each worker's timeline (`posted`: the run's request went to the worker).
    first_frame_ms: whole && whole.first_frame_ms != null ? Math.round(whole.first_frame_ms) : null,
    app_started_ms: timeline.app_started,
    pressed_ms: pressed && Math.round(pressed.clicked), menu_item_published: pressed && pressed.item_published,
    done_seen_ms: Math.round(doneAt),
    workers: timeline.workers,
    load: load(),
  };
  if (row.ray_updates && row.sim_ms) row.m_updates_per_s_whole = Math.round(row.ray_updates / row.sim_ms / 1e3 * 10) / 10;
  if (row.ray_updates && row.machining_seen_ms) row.m_updates_per_s_machining = Math.round(row.ray_updates / row.machining_seen_ms / 1e3 * 10) / 10;
  if (traceFile) await browser.stopTracing();
  report.runs.push(row);
  console.log(`run ${r + 1}: ${JSON.stringify(row)}`);
  if (r + 1 < runs) await page.close();
}

// Replays: drag the move slider to a new move and time release → exact stock at the move.
const s0 = sim(await status(page));
const slider = s0 && s0.ui && s0.ui.sim_move_slider;
if (slider) {
  const positions = [30, 70, 20, 90, 50, 10].slice(0, replays);
  for (const frac of positions) {
    const x = slider[0] + slider[2] * frac / 100;
    const y = slider[1] + slider[3] / 2;
    const before = sim(await status(page));
    await page.mouse.move(x - 5, y);
    await page.mouse.down();
    await page.mouse.move(x, y, { steps: 3 });
    await page.evaluate(() => { window.__frameGaps.length = 0; });
    await page.mouse.up();
    const t0 = Date.now();
    let st = null;
    let target = null;
    while (Date.now() - t0 < 300000) {
      const s = sim(await status(page));
      if (s) {
        target = s.target_move;
        if (s.stage === "done" && !s.computing && s.measured && s.moves_simulated === s.target_move
          && s.target_move !== before.target_move) { st = s; break; }
        // The drag landed on the move already shown: nothing to wait for.
        if (Date.now() - t0 > 3000 && s.target_move === before.target_move) break;
      }
      await page.waitForTimeout(20);
    }
    const gaps = await page.evaluate(() => window.__frameGaps.splice(0));
    const row = {
      target_move: target, release_to_exact_ms: st ? Date.now() - t0 : null, sim_ms: st && st.sim_ms,
      resumed_from_move: st && st.resumed_from_move,
      removed_volume_mm3: st && st.removed_volume_mm3, frame_longest_ms: gaps.length ? Math.max(...gaps) : null,
    };
    report.replays.push(row);
    console.log(`replay: ${JSON.stringify(row)}`);
  }
}
await page.screenshot({ path: path.join(artifacts, "sim-bench.png") });

// The worker alone: the recorded request in a bare worker on a page that draws nothing.
if (workerOnly > 0 && posted) {
  const other = jsFlags ? await chromium.launch({
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium", headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--no-first-run", `--js-flags=${jsFlags}`],
  }) : null;
  const bare = other ? await other.newPage() : await context.newPage();
  await bare.goto(new URL("assets/manifest.json", url).href);
  for (let r = 0; r < workerOnly; r++) {
    const row = await bare.evaluate(async ({ script, message }) => {
      const t0 = performance.now();
      const w = new Worker(script);
      let ready = null;
      let start = null;
      let progress = 0;
      let partials = 0;
      let partialChars = 0;
      const out = await new Promise((resolve) => {
        w.onmessage = (e) => {
          const text = String(e.data);
          const kind = text.slice(0, text.indexOf("\n"));
          if (kind === "ready") { ready = performance.now() - t0; start = performance.now(); w.postMessage(message); }
          else if (kind === "progress") progress++;
          else if (kind === "partial") { partials++; partialChars += text.length; }
          else resolve({ kind, chars: text.length });
        };
        w.onerror = (e) => resolve({ kind: "error", message: String(e.message) });
      });
      const job = performance.now() - start;
      w.terminate();
      return { worker_ready_ms: Math.round(ready), job_ms: Math.round(job), answer: out.kind, output_chars: out.chars,
        progress_messages: progress, partials, partial_chars: partialChars };
    }, { script: new URL("interpolab-worker_loader.js", url).href, message: posted });
    row.load = load();
    row.js_flags = jsFlags;
    report.worker_only.push(row);
    console.log(`worker only: ${JSON.stringify(row)}`);
  }
  await bare.close();
  if (other) await other.close();
} else if (workerOnly > 0) {
  console.log("worker only: no simulate-run request was recorded on the page");
}
report.load_at_end = load();
report.console = errors.slice(0, 20);
fs.writeFileSync(path.join(artifacts, "sim-bench.json"), JSON.stringify(report, null, 2));
console.log(`load ${report.load_at_start} → ${report.load_at_end}; written e2e/artifacts/sim-bench.json`);
await browser.close();
