// Profiles the release web app's frames in headless Chromium (SwiftShader, 1400×900), one tab
// at a time on a page of its own (the end-to-end test keeps several pages open, which share
// the GPU process). Not a test: it measures and reports, and asserts nothing.
//
//   node e2e/frame-profile.mjs http://127.0.0.1:PORT/ [--trace] [--cpu] [--tabs crease,chords]
//        [--variants "none;hide=plot;hide=view3d"] [--rounds 2] [--no-floor]
//        [--floor "draws=200;shapes=200;fills=1"] [--shots]
//
// Per tab: the gaps between animation frames and the app's own frame count while idle (does
// the idle page redraw?), while the mouse moves over the view (each move redraws: the cost of
// a frame with nothing to compute), and while dragging the tab's slider (the e2e test's drag).
// The floor: a page whose only content is a 1400×900 WebGL2 canvas cleared every frame, and
// the app's own empty frame (`?probe=floor`: an egui frame with nothing in it).
// --trace: a Chromium trace of the redraw and drag phases, summarised as busy time per thread
// (the page's main thread runs the wasm, the GPU process runs SwiftShader), and every frame
// over 50 ms one by one (its wasm callback, the GPU process's busy time, and with the variant
// `hide=marks` the 3D renderer's marks: scene passes, uploads); --cpu: the page's
// main-thread CPU profile (self time per function, wasm names included).
// --variants: A/B runs on the same build, interleaved: each round opens every tab once per
// variant, a variant being a query added to the address (`none`: the page as it is), e.g. the
// ablation switches `hide=…` (`src/app/ablate.rs`), or the address of another build
// (`http://127.0.0.1:8822/`); --rounds: how many rounds (default 1).
// Every row carries the load average before and after it (the machine is shared).
// --floor: the app's empty frame again with extras drawn (`?probe=floor&fills=1`: one
// translucent full-window rectangle; `draws=N`: N small rectangles each in a clip rectangle of
// its own, i.e. N draw calls; `shapes=N`: the same in one clip rectangle), --rounds times.
// --shots: a screenshot of each tab and variant once computed, before any input
// (e2e/artifacts/shots/TAB--VARIANT.png), to compare what the variants look like.
// Writes e2e/artifacts/frame-profile.json.
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { openBrowser } from "./browser.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const url = args.find((a) => a.startsWith("http")) ?? "http://127.0.0.1:8765/";
const wantTrace = args.includes("--trace");
const wantCpu = args.includes("--cpu");
const tabsArg = args[args.indexOf("--tabs") + 1];
const onlyTabs = args.includes("--tabs") && tabsArg ? tabsArg.split(",") : null;
const variantsArg = args.includes("--variants") ? args[args.indexOf("--variants") + 1] : "none";
const variants = variantsArg.split(";").map((v) => v.trim()).filter((v) => v.length > 0);
const rounds = args.includes("--rounds") ? Number(args[args.indexOf("--rounds") + 1]) : 1;
const wantFloor = !args.includes("--no-floor");
const wantShots = args.includes("--shots");
const load1 = () => Math.round(os.loadavg()[0] * 100) / 100;
const artifacts = path.join(here, "artifacts");
fs.mkdirSync(artifacts, { recursive: true });
const examples = path.join(here, "..", "examples");

function base64url(text) {
  return Buffer.from(text, "utf8").toString("base64").replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

const { browser, context } = await openBrowser();
// Every page starts from the same state: the app keeps the last scene in local storage, and a
// drag on one page would change the scene the next page opens with (and so what its drag does).
await context.addInitScript(() => window.localStorage.clear());

async function status(page) {
  const text = await page.locator("#app-status").textContent().catch(() => null);
  return text ? JSON.parse(text) : null;
}
async function waitFor(page, what, pred, timeoutMs = 120000) {
  const t0 = Date.now();
  let last = null;
  while (Date.now() - t0 < timeoutMs) {
    last = await status(page).catch(() => null);
    if (last && pred(last)) return last;
    await page.waitForTimeout(100);
  }
  throw new Error(`timed out waiting for ${what}`);
}
const settled = (s) => s.frames >= 3 && !s.running && s.periods >= 0 && s.stop !== null;

function summary(gaps) {
  if (gaps.length === 0) return { frames: 0 };
  const s = [...gaps].sort((a, b) => a - b);
  const q = (f) => s[Math.min(s.length - 1, Math.floor(f * s.length))];
  const r = (x) => Math.round(x * 10) / 10;
  return { frames: gaps.length, median_ms: r(q(0.5)), p90_ms: r(q(0.9)), p99_ms: r(q(0.99)), longest_ms: r(s[s.length - 1]) };
}
async function takeGaps(page) {
  return page.evaluate(() => window.__frameGaps.splice(0));
}

// Busy time per thread from a Chromium trace: the top-level tasks' durations (ms), and the
// page's animation-frame callbacks (the wasm frame) one by one.
function traceSummary(buffer) {
  const events = JSON.parse(buffer.toString("utf8")).traceEvents ?? [];
  const names = new Map();
  const procs = new Map();
  for (const e of events) {
    if (e.ph === "M" && e.name === "thread_name") names.set(`${e.pid}:${e.tid}`, e.args.name);
    if (e.ph === "M" && e.name === "process_name") procs.set(e.pid, e.args.name);
  }
  const busy = new Map();
  let t0 = Infinity;
  let t1 = -Infinity;
  const raf = [];
  const gpuTasks = [];
  for (const e of events) {
    if (e.ph !== "X" || typeof e.dur !== "number") continue;
    t0 = Math.min(t0, e.ts);
    t1 = Math.max(t1, e.ts + e.dur);
    const key = `${procs.get(e.pid) ?? e.pid}/${names.get(`${e.pid}:${e.tid}`) ?? e.tid}`;
    if (e.name === "ThreadControllerImpl::RunTask" || e.name === "ThreadPool_RunTask") {
      busy.set(key, (busy.get(key) ?? 0) + e.dur / 1000);
      if (/GPU/i.test(procs.get(e.pid) ?? "") && /CrGpuMain/.test(names.get(`${e.pid}:${e.tid}`) ?? "")) gpuTasks.push(e.dur / 1000);
    }
    if (e.name === "FireAnimationFrame") raf.push(e.dur / 1000);
  }
  const wall = (t1 - t0) / 1000;
  // The long frames one by one: gaps of over 50 ms between the page's animation-frame
  // callbacks, each with the callback that opened it (the wasm frame), the GPU process's main
  // thread's busy time in the gap and its longest kinds of work there (nested events counted
  // each), the page's main thread's busy time, and the app's performance marks (`?hide=marks`:
  // 3D scene passes and uploads) from the gap before it to its end (the GPU draws a frame
  // after the page's callback issued it).
  const isGpuMain = (e) => /GPU/i.test(procs.get(e.pid) ?? "") && /CrGpuMain/.test(names.get(`${e.pid}:${e.tid}`) ?? "");
  const rafEvents = events.filter((e) => e.ph === "X" && e.name === "FireAnimationFrame").sort((a, b) => a.ts - b.ts);
  const marks = events.filter((e) => /user_timing/.test(e.cat ?? "") && (e.ph === "R" || e.ph === "I" || e.ph === "n" || e.ph === "b"))
    .map((e) => ({ ts: e.ts, name: e.name })).sort((a, b) => a.ts - b.ts);
  const longFrames = [];
  for (let i = 1; i < rafEvents.length; i++) {
    const [a, b] = [rafEvents[i - 1].ts, rafEvents[i].ts];
    const gap = (b - a) / 1000;
    if (gap <= 50) continue;
    const before = i >= 2 ? rafEvents[i - 2].ts : a;
    const inGap = (e) => e.ts < b && e.ts + e.dur > a;
    const overlap = (e) => (Math.min(b, e.ts + e.dur) - Math.max(a, e.ts)) / 1000;
    let gpuBusy = 0;
    let pageBusy = 0;
    const kinds = new Map();
    for (const e of events) {
      if (e.ph !== "X" || typeof e.dur !== "number" || !inGap(e)) continue;
      const top = e.name === "ThreadControllerImpl::RunTask";
      if (isGpuMain(e)) {
        if (top) gpuBusy += overlap(e);
        else if (e.dur >= 1000) kinds.set(e.name, (kinds.get(e.name) ?? 0) + overlap(e));
      } else if (top && /Renderer/i.test(procs.get(e.pid) ?? "") && /CrRendererMain/.test(names.get(`${e.pid}:${e.tid}`) ?? "")) {
        pageBusy += overlap(e);
      }
    }
    longFrames.push({
      gap_ms: Math.round(gap),
      raf_ms: Math.round(rafEvents[i - 1].dur / 100) / 10,
      gpu_main_busy_ms: Math.round(gpuBusy),
      page_main_busy_ms: Math.round(pageBusy),
      gpu_work: [...kinds.entries()].sort((x, y) => y[1] - x[1]).slice(0, 5).map(([k, ms]) => `${k} ${Math.round(ms)}`),
      marks: marks.filter((m) => m.ts >= before && m.ts < b).map((m) => m.name),
    });
  }
  const threads = [...busy.entries()].sort((a, b) => b[1] - a[1]).slice(0, 8)
    .map(([k, ms]) => ({ thread: k, busy_ms: Math.round(ms), share: Math.round((100 * ms) / wall) + "%" }));
  return { wall_ms: Math.round(wall), threads, animation_frame_callbacks: summary(raf), gpu_main_tasks: summary(gpuTasks), long_frames: longFrames };
}

// Self time per function from a CDP CPU profile, top `n`.
function cpuSummary(profile, n = 30) {
  const self = new Map();
  const byId = new Map(profile.nodes.map((x) => [x.id, x]));
  const dt = new Map();
  for (let i = 0; i < profile.samples.length; i++) {
    const id = profile.samples[i];
    dt.set(id, (dt.get(id) ?? 0) + (profile.timeDeltas[i] ?? 0) / 1000);
  }
  let total = 0;
  for (const [id, ms] of dt) {
    const node = byId.get(id);
    const name = node.callFrame.functionName || `(${node.callFrame.url.split("/").pop() || "anonymous"})`;
    self.set(name, (self.get(name) ?? 0) + ms);
    total += ms;
  }
  return {
    total_ms: Math.round(total),
    top: [...self.entries()].sort((a, b) => b[1] - a[1]).slice(0, n).map(([f, ms]) => `${Math.round(ms)} ms  ${f}`),
  };
}

async function withProbes(page, label, fn) {
  let cdp = null;
  if (wantCpu) {
    cdp = await page.context().newCDPSession(page);
    await cdp.send("Profiler.enable");
    await cdp.send("Profiler.setSamplingInterval", { interval: 500 });
    await cdp.send("Profiler.start");
  }
  if (wantTrace) {
    await browser.startTracing(page, {
      categories: ["toplevel", "devtools.timeline", "disabled-by-default-devtools.timeline", "gpu", "viz", "cc", "blink.user_timing"],
    });
  }
  const out = await fn();
  if (wantTrace) out.trace = traceSummary(await browser.stopTracing());
  if (cdp) {
    const { profile } = await cdp.send("Profiler.stop");
    out.cpu = cpuSummary(profile);
    fs.writeFileSync(path.join(artifacts, `frame-profile-${label}.cpuprofile`), JSON.stringify(profile));
    await cdp.detach();
  }
  return out;
}

// Moves the mouse to and fro over a rectangle: every move makes egui draw a frame, so this
// measures a redraw with nothing new to compute.
async function hover(page, r, moves = 40) {
  for (let i = 0; i < moves; i++) {
    const f = (i % 10) / 10;
    await page.mouse.move(r[0] + r[2] * (0.3 + 0.4 * f), r[1] + r[3] * (0.4 + 0.2 * f));
    await page.waitForTimeout(30);
  }
}
async function dragSlider(p, r, from = 40, to = 70, steps = 10) {
  await p.mouse.move(r[0] + from, r[1] + r[3] / 2);
  await p.mouse.down();
  await p.mouse.move(r[0] + to, r[1] + r[3] / 2, { steps });
  await p.mouse.up();
}

const TABS = [
  { id: "crease", title: null, scene: null, slider: (s) => s.ui.feed_slider, done: (s) => settled(s) },
  { id: "fiveaxis", title: "5-axis steps", slider: (s) => s.panel.status.ui.tolerance, done: (s) => s.panel.status.computing === false },
  { id: "chords", title: "Chords", slider: (s) => s.panel.status.ui.tolerance, done: (s) => s.panel.status.computing === false },
  { id: "nurbs", title: "NURBS & G-code", scene: "torus-plane.json", slider: (s) => s.panel.status.ui.tolerance_slider, done: (s) => s.panel.status.done },
  { id: "simulation", title: "Cutting simulation", slider: (s) => s.panel.status.ui.sim_move_slider, from: 90, to: 50,
    done: (s) => s.panel.status.stage === "done" && s.panel.status.computing === false },
  { id: "fillet", title: "Fillet end mill", slider: (s) => s.panel.status.ui.scallop_slider,
    done: (s) => s.panel.status.computing === false && s.panel.status.passes > 0 },
];

const report = { url, load_average: os.loadavg().map((x) => Math.round(x * 100) / 100), floor: {}, tabs: {} };

// The floor of the browser: a 1400×900 WebGL2 canvas cleared every frame, nothing else.
if (wantFloor) {
  const page = await context.newPage();
  await page.setContent(`<canvas id="c" width="1400" height="900" style="position:absolute;inset:0"></canvas><script>
    const gl = document.getElementById("c").getContext("webgl2");
    let k = 0;
    const draw = () => { k++; gl.clearColor((k % 60) / 60, 0.1, 0.2, 1); gl.clear(gl.COLOR_BUFFER_BIT); requestAnimationFrame(draw); };
    requestAnimationFrame(draw);
  </script>`);
  await page.waitForTimeout(500);
  await takeGaps(page);
  await page.waitForTimeout(2000);
  report.floor.webgl2_clear = summary(await takeGaps(page));
  await page.close();
}
// The app's empty egui frame (if this build knows `?probe=floor`), and with the extras asked
// for by --floor (`draws=N`, `shapes=N`, `fills=N`: see `FloorExtra` in src/app/web.rs).
const floorExtras = args.includes("--floor") ? args[args.indexOf("--floor") + 1].split(";") : [];
for (let round = 1; wantFloor && round <= (floorExtras.length ? rounds : 1); round++) {
  for (const extra of ["", ...floorExtras]) {
    const page = await context.newPage();
    await page.goto(url + "?probe=floor" + (extra ? "&" + extra : ""));
    await page.waitForTimeout(3000);
    const s = await status(page);
    if (s && s.probe === "floor") {
      await takeGaps(page);
      await page.waitForTimeout(2000);
      const row = { ...summary(await takeGaps(page)), load: load1() };
      if (!extra && round === 1) report.floor.egui_empty = row;
      (report.floor.extras ??= []).push({ round, extra: extra || "none", ...row });
      if (floorExtras.length) console.log(`floor [${extra || "none"}] round ${round}`, JSON.stringify(row));
    }
    await page.close();
  }
}
console.log("floor", JSON.stringify(report.floor));

async function profileTab(tab, variant) {
  const page = await context.newPage();
  const scene = tab.scene ? "#scene=" + base64url(fs.readFileSync(path.join(examples, tab.scene), "utf8")) : "";
  // A variant is a query for this build, or another build's address (`http…`, A/B of builds).
  const base = variant.startsWith("http") ? variant : url;
  const query = variant === "none" || variant.startsWith("http") ? "" : "?" + variant;
  await page.goto(base + query + scene);
  let s = await waitFor(page, "the first path", settled);
  if (tab.title) {
    const r = s.ui[tab.title];
    await page.mouse.click(r[0] + r[2] / 2, r[1] + r[3] / 2);
    s = await waitFor(page, `${tab.id} computed`, (x) => x.panel && x.panel.title === tab.title && x.panel.status && tab.done(x));
  }
  await page.waitForTimeout(1500);
  if (wantShots) {
    const dir = path.join(artifacts, "shots");
    fs.mkdirSync(dir, { recursive: true });
    const slug = variant.replace(/^https?:\/\//, "").replace(/[^A-Za-z0-9=,.-]+/g, "_");
    await page.screenshot({ path: path.join(dir, `${tab.id}--${slug}.png`) });
  }
  const row = {};
  // Idle: no input. An idle page should draw no frames of its own.
  await takeGaps(page);
  const f0 = (await status(page)).frames;
  await page.waitForTimeout(2000);
  const f1 = (await status(page)).frames;
  row.idle = { ...summary(await takeGaps(page)), app_frames_in_2s: f1 - f0 };
  const view = s.panel?.status?.ui?.view ?? [420, 100, 900, 450];
  Object.assign(row, await withProbes(page, `${tab.id}`, async () => {
    const out = {};
    await takeGaps(page);
    const g0 = (await status(page)).frames;
    await hover(page, view);
    const g1 = (await status(page)).frames;
    out.redraw = { ...summary(await takeGaps(page)), app_frames: g1 - g0 };
    s = await status(page);
    const r = tab.slider(s);
    if (r) {
      await takeGaps(page);
      const before = JSON.stringify(tab.id === "crease" ? s.feed_mm_per_min : s.panel.status);
      await dragSlider(page, r, tab.from ?? 40, tab.to ?? 70);
      await page.waitForTimeout(300);
      await waitFor(page, `${tab.id} after the drag`, (x) => (tab.id === "crease" ? settled(x) : tab.done(x))
        && JSON.stringify(tab.id === "crease" ? x.feed_mm_per_min : x.panel.status) !== before);
      out.drag = summary(await takeGaps(page));
    }
    return out;
  }));
  await page.close();
  return row;
}

report.runs = [];
for (let round = 1; round <= rounds; round++) {
  for (const variant of variants) {
    for (const tab of TABS) {
      if (onlyTabs && !onlyTabs.includes(tab.id)) continue;
      const loadBefore = load1();
      const row = await profileTab(tab, variant);
      row.load = [loadBefore, load1()];
      report.runs.push({ round, variant, tab: tab.id, ...row });
      if (rounds === 1 && variants.length === 1) report.tabs[tab.id] = row;
      console.log(`${tab.id} [${variant}] round ${round} load ${row.load.join("–")}`,
        JSON.stringify({ idle: row.idle, redraw: row.redraw, drag: row.drag }));
      if (row.trace) console.log("   trace", JSON.stringify(row.trace));
      if (row.cpu) console.log("   cpu", row.cpu.total_ms, "ms\n     " + row.cpu.top.slice(0, 20).join("\n     "));
    }
  }
}
// One line per variant and tab: each round's redraw and drag figures side by side.
for (const variant of variants) {
  for (const tab of TABS) {
    const rs = report.runs.filter((r) => r.variant === variant && r.tab === tab.id);
    if (rs.length === 0) continue;
    console.log(`summary ${tab.id} [${variant}]: redraw median ${rs.map((r) => r.redraw?.median_ms).join("/")} ms,`
      + ` drag median ${rs.map((r) => r.drag?.median_ms).join("/")} ms, drag p99 ${rs.map((r) => r.drag?.p99_ms).join("/")},`
      + ` drag longest ${rs.map((r) => r.drag?.longest_ms).join("/")} ms, load ${rs.map((r) => r.load.join("–")).join(", ")}`);
  }
}
report.load_average_after = os.loadavg().map((x) => Math.round(x * 100) / 100);
fs.writeFileSync(path.join(artifacts, "frame-profile.json"), JSON.stringify(report, null, 2));
await browser.close();
