// End-to-end test of the release web app in Debian's headless Chromium (driven by
// playwright-core; no browser download). Usage: node e2e/e2e.mjs http://127.0.0.1:PORT/
//
// Checks, as a new user would meet them: the page loads and draws its first frame (pixels,
// not just logs), no console error, moving the feed slider changes the number of periods,
// a bad scene file shows an error and keeps the scene, a share link restores the scene,
// the last scene survives a reload, the 5-axis and chords tabs draw and compute (Example 1
// before and after, the iteration table following the tolerance). Screenshots go to
// e2e/artifacts/.
import { chromium } from "playwright-core";
import { PNG } from "pngjs";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { openBrowser } from "./browser.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const url = process.argv[2] ?? "http://127.0.0.1:8765/";
const artifacts = path.join(here, "artifacts");
fs.mkdirSync(artifacts, { recursive: true });
const examples = path.join(here, "..", "examples");

// The machine's load when the run starts and ends (frame times on a shared CPU depend on it).
const loadAverage = () => os.loadavg().map((x) => Math.round(x * 100) / 100);
const loadAtStart = loadAverage();
const results = [];
function check(name, ok, detail = "") {
  results.push({ name, ok });
  console.log(`${ok ? "ok  " : "FAIL"}  ${name}${detail ? " — " + detail : ""}`);
}

function base64url(text) {
  return Buffer.from(text, "utf8").toString("base64").replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

async function status(page) {
  const text = await page.locator("#app-status").textContent();
  return text ? JSON.parse(text) : null;
}

async function waitFor(page, what, pred, timeoutMs = 60000) {
  const t0 = Date.now();
  let last = null;
  while (Date.now() - t0 < timeoutMs) {
    last = await status(page).catch(() => null);
    if (last && pred(last)) return last;
    await page.waitForTimeout(100);
  }
  throw new Error(`timed out waiting for ${what}; last status: ${JSON.stringify(last)}`);
}

const settled = (s) => s.frames >= 3 && !s.running && s.periods >= 0 && s.stop !== null;

// Fraction of distinct colours in a region of a screenshot: a blank canvas has one.
function colourVariety(pngBuffer, region) {
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

const { browser, context } = await openBrowser();
// Frame gaps (`window.__frameGaps`, recorded on every page by openBrowser): measured,
// reported, not asserted: timings on a shared CPU are no test.
const frameReport = [];
// Drags a slider by its published rectangle [x, y, w, h] from `from` to `to` points along
// its rail, in small steps as a hand would.
async function dragSlider(p, r, from = 40, to = 70, steps = 10) {
  await p.mouse.move(r[0] + from, r[1] + r[3] / 2);
  await p.mouse.down();
  await p.mouse.move(r[0] + to, r[1] + r[3] / 2, { steps });
  await p.mouse.up();
}
async function resetFrames(p) {
  await p.evaluate(() => { window.__frameGaps.length = 0; });
}
async function recordFrames(p, label) {
  const gaps = await p.evaluate(() => window.__frameGaps.splice(0));
  if (gaps.length === 0) return;
  const sorted = [...gaps].sort((a, b) => a - b);
  const q = (f) => sorted[Math.min(sorted.length - 1, Math.floor(f * sorted.length))];
  const row = { label, tab: currentTab, frames: gaps.length, median_ms: q(0.5), p99_ms: q(0.99), longest_ms: sorted[sorted.length - 1] };
  frameReport.push(row);
  console.log(`      frames while ${label}: ${row.frames}, median ${row.median_ms.toFixed(1)} ms, p99 ${row.p99_ms.toFixed(1)} ms, longest ${row.longest_ms.toFixed(1)} ms`);
}
let currentTab = "crease";
const consoleErrors = [];
context.on("console", (m) => { if (m.type() === "error") consoleErrors.push(m.text()); });
context.on("weberror", (e) => consoleErrors.push(String(e.error())));

let failed = false;
try {
  // 1. Load, first frame.
  const page = await context.newPage();
  const t0 = Date.now();
  await page.goto(url);
  const s0 = await waitFor(page, "the first computed path", settled);
  const loadMs = Date.now() - t0;
  const shot0 = await page.screenshot({ path: path.join(artifacts, "01-first-frame.png") });
  const variety = colourVariety(shot0, [420, 60, 900, 520]);
  check("page loads and computes the preset", s0.periods > 100, `${s0.periods} periods, ${s0.scene}`);
  check("first frame is drawn (3D view not blank)", variety > 40, `${variety} distinct colours in the view`);
  check("time to first frame recorded", typeof s0.first_frame_ms === "number", `first frame at ${Math.round(s0.first_frame_ms)} ms after navigation; settled after ${loadMs} ms`);

  // 2. Feed slider.
  // The slider's rail is its first 100 points; press on it and drag a little to the right.
  const [x, y, , h] = s0.ui.feed_slider;
  const handleY = y + h / 2;
  await resetFrames(page);
  await page.mouse.move(x + 40, handleY);
  await page.mouse.down();
  await page.mouse.move(x + 70, handleY, { steps: 8 });
  await page.mouse.up();
  const s1 = await waitFor(page, "the path after moving the feed slider", (s) => s.feed_mm_per_min !== s0.feed_mm_per_min && settled(s));
  await recordFrames(page, "dragging the crease's feed slider");
  await page.screenshot({ path: path.join(artifacts, "02-after-feed-slider.png") });
  check("moving the feed slider changes the number of periods", s1.periods !== s0.periods,
    `feed ${s0.feed_mm_per_min} → ${s1.feed_mm_per_min.toFixed(1)} mm/min, periods ${s0.periods} → ${s1.periods}`);

  // 3. A bad scene file is refused; the scene is kept.
  const bad = JSON.parse(fs.readFileSync(path.join(examples, "torus-plane.json"), "utf8"));
  bad.tool.radius = -2;
  await page.setInputFiles("#scene-file", { name: "bad-scene.json", mimeType: "application/json", buffer: Buffer.from(JSON.stringify(bad)) });
  const s2 = await waitFor(page, "the error about the bad file", (s) => s.error.includes("bad-scene.json"));
  await page.screenshot({ path: path.join(artifacts, "03-bad-file.png") });
  check("a bad scene file shows what is wrong", s2.error.includes("tool.radius") && s2.error.includes("kept"), s2.error);
  check("… and keeps the current scene", s2.scene === s1.scene && s2.periods === s1.periods);

  // 4. A good file opens.
  await page.setInputFiles("#scene-file", { name: "torus.json", mimeType: "application/json", buffer: fs.readFileSync(path.join(examples, "torus-plane.json")) });
  const s3 = await waitFor(page, "the opened file", (s) => s.scene.startsWith("Torus") && settled(s));
  check("a scene file opens", s3.periods > 100, `${s3.scene}: ${s3.periods} periods`);

  // 5. The app's share link restores the scene in a fresh page.
  const sb = s3.ui.share_button;
  await page.mouse.click(sb[0] + sb[2] / 2, sb[1] + sb[3] / 2);
  await page.waitForTimeout(300);
  const shared = page.url();
  check("Share link puts the scene in the URL", shared.includes("#scene="), `${shared.length} characters`);
  const page2 = await context.newPage();
  await page2.goto("about:blank");
  await page2.goto(shared);
  const s4 = await waitFor(page2, "the shared scene", settled);
  await page2.screenshot({ path: path.join(artifacts, "04-share-link.png") });
  check("a share link restores the scene", s4.scene === s3.scene && s4.periods === s3.periods, `${s4.scene}, ${s4.periods} periods`);

  // 6. A link built outside the app (another example) opens too.
  const dome = JSON.parse(fs.readFileSync(path.join(examples, "sphere-plane.json"), "utf8"));
  const page3 = await context.newPage();
  await page3.goto(url + "#scene=" + base64url(JSON.stringify(dome)));
  const s5 = await waitFor(page3, "the linked dome scene", (s) => s.scene === dome.name && settled(s));
  check("a hand-made link opens its scene", s5.periods > 100, `${s5.periods} periods`);

  // 6b. A run that goes away from path.end says which path.direction reaches it.
  const groove = JSON.parse(fs.readFileSync(path.join(here, "..", "tests", "data", "groove-end-behind-start.json"), "utf8"));
  const pageG = await context.newPage();
  await pageG.goto(url + "#scene=" + base64url(JSON.stringify(groove)));
  const sG = await waitFor(pageG, "the groove scene", (s) => s.scene === groove.name && settled(s));
  await pageG.screenshot({ path: path.join(artifacts, "05a-end-not-reached.png") });
  check("a run away from path.end names the path.direction to set",
    sG.stop === "left_domain" && (sG.end_note || "").includes("path.direction to [1.000, 0.000, 0.000]"), sG.end_note);
  const tb = sG.ui.run_toward_end;
  await pageG.mouse.click(tb[0] + tb[2] / 2, tb[1] + tb[3] / 2);
  const sG2 = await waitFor(pageG, "the run toward path.end", (s) => s.stop === "reached_end" && settled(s));
  await pageG.screenshot({ path: path.join(artifacts, "05b-end-reached.png") });
  check("its button runs toward path.end", sG2.end_note === null && sG2.periods === 800, `${sG2.periods} periods`);
  await pageG.close();

  // 7. A broken link shows an error and a usable scene.
  const page4 = await context.newPage();
  await page4.goto(url + "#scene=" + base64url('{"format":"interpolab-scene/1"}'));
  const s6 = await waitFor(page4, "the broken-link error", (s) => s.error !== "" && s.frames >= 3);
  await page4.screenshot({ path: path.join(artifacts, "05-broken-link.png") });
  check("a broken link says what is wrong", s6.error.includes("link") && s6.error.includes("missing"), s6.error);

  // 8. The 5-axis and chords tabs draw their views and compute (seed 002's Example 1 before
  // and after its steps are inserted, the iteration table following the tolerance slider;
  // seed 003's parabola).
  const page5 = await context.newPage();
  await page5.goto(url);
  const s8 = await waitFor(page5, "the app for the panel tabs", settled);
  const clickRect = async (p, r) => p.mouse.click(r[0] + r[2] / 2, r[1] + r[3] / 2);
  const panelDone = (title) => (s) => s.panel && s.panel.title === title && s.panel.status && s.panel.status.computing === false;
  await resetFrames(page5);
  currentTab = "5-axis";
  await clickRect(page5, s8.ui["5-axis (seed 002)"]);
  const f1 = await waitFor(page5, "the 5-axis view (Example 1, one block)", panelDone("5-axis (seed 002)"));
  await recordFrames(page5, "opening the 5-axis tab");
  await page5.waitForTimeout(500);
  const shot5a = await page5.screenshot({ path: path.join(artifacts, "06-fiveaxis-example1-before.png") });
  const p1 = f1.panel.status;
  check("5-axis tab: Example 1's single block gouges by 8.79 mm", p1.blocks === 2 && Math.abs(p1.worst_delta_mm - 8.79) < 0.01,
    `${p1.blocks} blocks, δ = ${p1.worst_delta_mm.toFixed(4)} mm`);
  const v1 = colourVariety(shot5a, p1.ui.view);
  check("5-axis tab: the 3D view is drawn (not blank)", v1 > 40, `${v1} distinct colours in the view`);
  await clickRect(page5, p1.ui.after);
  const f2 = await waitFor(page5, "Example 1 after the steps", (s) => panelDone("5-axis (seed 002)")(s) && !s.panel.status.before);
  await page5.waitForTimeout(500);
  await page5.screenshot({ path: path.join(artifacts, "07-fiveaxis-example1-after.png") });
  const p2 = f2.panel.status;
  check("5-axis tab: after the steps every segment is within E", p2.blocks === 32 && p2.worst_delta_mm <= p2.tol_mm && p2.error === "",
    `${p2.blocks} blocks, worst δ ${(p2.worst_delta_mm * 1e3).toFixed(4)} µm, E ${p2.tol_mm} mm, iterations ${JSON.stringify(p2.compare)}`);
  const [tx, ty, , th] = p2.ui.tolerance;
  await resetFrames(page5);
  await page5.mouse.move(tx + 40, ty + th / 2);
  await page5.mouse.down();
  await page5.mouse.move(tx + 15, ty + th / 2, { steps: 6 });
  await page5.mouse.up();
  const f3 = await waitFor(page5, "the plan at a new tolerance", (s) => panelDone("5-axis (seed 002)")(s) && s.panel.status.tol_mm !== p2.tol_mm);
  await recordFrames(page5, "dragging the 5-axis tolerance slider");
  const p3 = f3.panel.status;
  check("5-axis tab: the iteration table follows the tolerance slider",
    p3.blocks > p2.blocks && p3.compare.secant !== p2.compare.secant && Object.values(p3.compare).every((v) => Number.isInteger(v)),
    `E ${p2.tol_mm} → ${p3.tol_mm.toFixed(5)} mm: ${p3.blocks} blocks, ${JSON.stringify(p3.compare)}`);
  await clickRect(page5, p3.ui.bound_tip);
  const f3b = await waitFor(page5, "the plan with the tip bound", (s) => panelDone("5-axis (seed 002)")(s) && s.panel.status.bound_tip);
  await page5.waitForTimeout(500);
  await page5.screenshot({ path: path.join(artifacts, "07b-fiveaxis-tip-bound.png") });
  const p3b = f3b.panel.status;
  check("5-axis tab: the tip-bound switch replans within E",
    p3b.blocks >= p3.blocks && p3b.worst_delta_mm <= p3b.tol_mm && p3b.error === "", `${p3.blocks} → ${p3b.blocks} blocks`);
  await resetFrames(page5);
  await clickRect(page5, f3b.ui["Chords (seed 003)"]);
  const f4 = await waitFor(page5, "the chords view", panelDone("Chords (seed 003)"));
  await recordFrames(page5, "opening the chords tab");
  await page5.waitForTimeout(500);
  const shot5c = await page5.screenshot({ path: path.join(artifacts, "08-chords-parabola.png") });
  const rows = f4.panel.status.rows;
  check("chords tab: the parabola's equal-error chords are the fewest (seed 003)",
    rows["equal-error"].nodes === 18 && rows["equal-interval, sized by ρ_min"].nodes === 23 && rows["equal-step, sized by ρ_min"].nodes === 41,
    `${rows["equal-error"].nodes} / ${rows["equal-interval, sized by ρ_min"].nodes} / ${rows["equal-step, sized by ρ_min"].nodes} nodes at d = ${f4.panel.status.tol_mm} mm`);
  const v2 = colourVariety(shot5c, f4.panel.status.ui.plots);
  check("chords tab: the plots are drawn (not blank)", v2 > 12, `${v2} distinct colours in the plots`);
  currentTab = "chords";
  await resetFrames(page5);
  await dragSlider(page5, f4.panel.status.ui.tolerance);
  await waitFor(page5, "the chords at a new tolerance", (s) => panelDone("Chords (seed 003)")(s) && s.panel.status.tol_mm !== f4.panel.status.tol_mm);
  await recordFrames(page5, "dragging the chords tolerance slider");

  // 9. The last scene is kept across reloads (eframe stores it in local storage). Only
  // page3 stays open, so no other page overwrites the stored scene meanwhile.
  for (const p of [page, page2, page4, page5]) await p.close();
  await page3.waitForTimeout(6000); // auto-save interval 5 s
  await page3.goto(url);
  const s7 = await waitFor(page3, "the reloaded scene", settled);
  check("the last scene is kept across reloads", s7.scene === dome.name, s7.scene);

  await page3.close();

  // 9. NURBS & G-code panel (seed 004): the tab draws, its comparison is computed, a program
  // downloaded from it and loaded back is drawn and measured, a malformed one is refused
  // with its line.
  {
    const TAB = "NURBS & G-code (seed 004)";
    const pageN = await context.newPage();
    // Clicks a widget of the panel by its published rectangle until `pred` holds: the layout
    // moves when the banner above it comes and goes, so a rectangle can be a frame old.
    const clickUntil = async (what, key, pred) => {
      for (let i = 0; i < 5; i++) {
        const r = (await status(pageN)).panel.status.ui[key];
        await pageN.mouse.click(r[0] + r[2] / 2, r[1] + r[3] / 2);
        try {
          return await waitFor(pageN, what, pred, 2000);
        } catch {
          // the rectangle had moved; read it again
        }
      }
      throw new Error(`clicking ${key} did not give ${what}`);
    };
    await pageN.goto(url + "#scene=" + base64url(fs.readFileSync(path.join(examples, "torus-plane.json"), "utf8")));
    let sn = await waitFor(pageN, "the torus crease", settled);
    const tab = sn.ui[TAB];
    currentTab = "nurbs";
    await resetFrames(pageN);
    await pageN.mouse.click(tab[0] + tab[2] / 2, tab[1] + tab[3] / 2);
    const panelDone = (s) => s.panel && s.panel.title === TAB && s.panel.status && s.panel.status.done;
    const tn = Date.now();
    sn = await waitFor(pageN, "the NURBS panel's comparison", panelDone);
    await recordFrames(pageN, "the NURBS tab computes its comparison");
    const st = sn.panel.status;
    const shotN = await pageN.screenshot({ path: path.join(artifacts, "nurbs-1-panel.png") });
    const v = st.ui.view;
    const varietyN = colourVariety(shotN, [v[0], v[1], v[2], v[3]]);
    check("NURBS panel draws its 3D view (not blank)", varietyN > 40, `${varietyN} distinct colours in the view`);
    const blocks = st.rows.map((r) => `${r.kind} ${r.path_blocks}`).join(", ");
    check("NURBS panel compares the G01, G02/G03 and G06.2 programs", st.status_ok && st.rows.length === 3
      && st.rows.every((r) => r.fresh && r.path_blocks > 0 && r.deviation_mm <= st.tol_mm) && st.realtime.length === 3,
      `${blocks} path blocks at ${st.tol_mm} mm, in ${Date.now() - tn} ms`);
    // Download the G01 program, then open the downloaded file: it is drawn over the design
    // and its deviation is the one the table reports.
    await clickUntil("the G01 program shown", "G01", (s) => s.panel.status.program === "g01");
    const downloaded = pageN.waitForEvent("download", { timeout: 20000 });
    await clickUntil("the download", "download", (s) => (s.panel.status.downloaded ?? "").endsWith("-g01.nc"));
    const download = await downloaded;
    const file = path.join(artifacts, download.suggestedFilename());
    await download.saveAs(file);
    // Pixels of the loaded program's colour (yellow, 250 230 60) in the view.
    const yellow = (png) => {
      const img = PNG.sync.read(png);
      let n = 0;
      for (let y = Math.round(v[1]); y < v[1] + v[3]; y++) {
        for (let x = Math.round(v[0]); x < v[0] + v[2]; x++) {
          const i = (img.width * y + x) << 2;
          if (Math.abs(img.data[i] - 250) < 30 && Math.abs(img.data[i + 1] - 230) < 30 && img.data[i + 2] < 120) n++;
        }
      }
      return n;
    };
    const before = yellow(await pageN.screenshot());
    await pageN.setInputFiles("#scene-file", { name: download.suggestedFilename(), mimeType: "text/plain", buffer: fs.readFileSync(file) });
    sn = await waitFor(pageN, "the loaded program's deviation", (s) => panelDone(s) && s.panel.status.loaded?.deviation_mm != null);
    const loaded = sn.panel.status.loaded;
    const shotL = await pageN.screenshot({ path: path.join(artifacts, "nurbs-2-loaded-program.png") });
    const after = yellow(shotL);
    check("a downloaded program loads back with the table's deviation",
      download.suggestedFilename().endsWith(".nc") && loaded.error === null
        && Math.abs(loaded.deviation_mm - st.rows[0].deviation_mm) < 1e-9,
      `${loaded.name}: ${(loaded.deviation_mm * 1000).toFixed(3)} µm (table ${(st.rows[0].deviation_mm * 1000).toFixed(3)} µm), worst at line ${loaded.deviation_line}`);
    check("… and is drawn over the design", sn.panel.status.worst_px !== null && after > before + 200,
      `${after} yellow pixels (${before} before), worst-deviation marker at ${sn.panel.status.worst_px.map(Math.round)}`);
    // A malformed program: an error naming the line, the page keeps working.
    const bad = "%\nG21 G90\nG00 X0 Y0 Z5\nG01 X10 Y#1 F500\nM30\n%\n";
    await pageN.setInputFiles("#scene-file", { name: "bad.ngc", mimeType: "text/plain", buffer: Buffer.from(bad) });
    sn = await waitFor(pageN, "the malformed program's error", (s) => s.error.includes("bad.ngc"));
    await pageN.screenshot({ path: path.join(artifacts, "nurbs-3-bad-program.png") });
    check("a malformed G-code file shows the line and the fix", sn.error.includes("line 4") && sn.error.includes("plain numbers")
      && sn.panel.status.loaded.error.includes("line 4"), sn.error);
    // Drag the tolerance slider: the three programs are written again (in Web Workers).
    await resetFrames(pageN);
    const td = Date.now();
    await dragSlider(pageN, (await status(pageN)).panel.status.ui.tolerance_slider);
    const sd = await waitFor(pageN, "the comparison at a new tolerance", (s) => panelDone(s) && s.panel.status.tol_mm !== st.tol_mm);
    await recordFrames(pageN, "dragging the NURBS tolerance slider");
    check("NURBS panel: the comparison follows the tolerance slider", sd.panel.status.rows.length === 3
      && sd.panel.status.rows.every((r) => r.fresh && r.deviation_mm <= sd.panel.status.tol_mm),
      `E ${st.tol_mm} → ${sd.panel.status.tol_mm.toFixed(4)} mm, recomputed in ${Date.now() - td} ms`);
    check("NURBS panel: its programs are written in Web Workers, not on the page",
      sd.jobs.background >= 6 && sd.jobs.on_page === 0, JSON.stringify(sd.jobs));
    await pageN.close();
  }

  // 10. Cutting simulation: the scene's crease program machined into a dexel stock, move by
  // move over frames, measured against the design.
  {
    const TAB = "Cutting simulation";
    const pageS = await context.newPage();
    await pageS.goto(url);
    let ss = await waitFor(pageS, "the app for the simulation tab", settled);
    const tabS = ss.ui[TAB];
    currentTab = "simulation";
    await resetFrames(pageS);
    await pageS.mouse.click(tabS[0] + tabS[2] / 2, tabS[1] + tabS[3] / 2);
    ss = await waitFor(pageS, "the cutting simulation", (s) => s.panel && s.panel.title === TAB && s.panel.status
      && s.panel.status.stage === "done" && s.panel.status.computing === false, 120000);
    await recordFrames(pageS, "the simulation tab machines the crease program");
    await pageS.waitForTimeout(500);
    const shotS = await pageS.screenshot({ path: path.join(artifacts, "11-cutting-simulation.png") });
    const st = ss.panel.status;
    check("simulation tab: the crease program is machined, every move",
      st.error === null && st.moves_total > 0 && st.moves_simulated === st.moves_total && st.removed_volume_mm3 > 0
        && st.grid.nx <= 256 && st.grid.ny <= 256,
      `${st.moves_simulated}/${st.moves_total} moves on ${st.grid.nx}×${st.grid.ny} rays at ${st.grid.pitch_mm} mm, ${st.removed_volume_mm3} mm³ removed, slowest step ${st.slowest_frame_ms} ms`);
    check("simulation tab: scallops and gouges are measured against the design",
      st.scallop_um !== null && st.scallop_um.rays > 0, JSON.stringify({ scallop_um: st.scallop_um, gouge: st.gouge }));
    const vS = colourVariety(shotS, [420, 60, 900, 520]);
    check("simulation tab: the machined stock is drawn (not blank)", vS > 40, `${vS} distinct colours in the view`);
    // Scrub the move slider back: the stock is machined again up to that move.
    const ms = st.ui && st.ui.sim_move_slider;
    if (ms) {
      await resetFrames(pageS);
      // The rail is the slider's first 100 points (the rest is its text).
      await dragSlider(pageS, ms, 90, 50);
      await waitFor(pageS, "the stock at the scrubbed move", (s) => s.panel.status.computing === false
        && s.panel.status.moves_simulated !== st.moves_simulated, 120000);
      await recordFrames(pageS, "dragging the simulation's move slider");
    }
    await pageS.close();
  }

  // 10b. The cutting simulation as a background job: the program is made, machined and
  // measured in a Web Worker (the core's second wasm module), the page only draws what
  // comes back; the view is orbited while it computes (frames recorded), and the move
  // slider shows a keyframe at once, then the exact stock from a run to that move.
  {
    const TAB = "Cutting simulation";
    const pageJ = await context.newPage();
    await pageJ.goto(url);
    let sj = await waitFor(pageJ, "the app for the simulation job", settled);
    const jobs0 = sj.jobs;
    const tabJ = sj.ui[TAB];
    currentTab = "simulation";
    await pageJ.mouse.click(tabJ[0] + tabJ[2] / 2, tabJ[1] + tabJ[3] / 2);
    await resetFrames(pageJ);
    // Orbit the view (drag across it) while the worker machines.
    const t0 = Date.now();
    for (let i = 0; i < 6; i++) {
      await pageJ.mouse.move(700, 400);
      await pageJ.mouse.down();
      await pageJ.mouse.move(760 + 10 * i, 430, { steps: 8 });
      await pageJ.mouse.up();
      const now = await status(pageJ);
      if (now.panel && now.panel.status && now.panel.status.stage === "done") break;
    }
    sj = await waitFor(pageJ, "the simulation job", (s) => s.panel && s.panel.title === TAB && s.panel.status
      && s.panel.status.stage === "done" && s.panel.status.computing === false, 120000);
    await recordFrames(pageJ, "orbiting the view while the simulation job machines");
    const jt = sj.panel.status;
    check("simulation job: machined and measured in a Web Worker, not on the page",
      jt.in_background === true && sj.jobs.background > jobs0.background && sj.jobs.on_page === jobs0.on_page
        && jt.moves_simulated === jt.moves_total && jt.scallop_um !== null,
      `${jt.moves_total} moves, ${jt.removed_volume_mm3} mm³ in ${Math.round(jt.sim_ms)} ms wall (${Date.now() - t0} ms to done), longest frame on it ${jt.slowest_frame_ms.toFixed(1)} ms, jobs ${JSON.stringify(sj.jobs)}`);
    const msj = jt.ui && jt.ui.sim_move_slider;
    if (msj) {
      await resetFrames(pageJ);
      const ts = Date.now();
      await dragSlider(pageJ, msj, 90, 30, 12);
      const back = await waitFor(pageJ, "the exact stock at the scrubbed move", (s) => s.panel.status.computing === false
        && s.panel.status.stage === "done" && s.panel.status.moves_simulated < jt.moves_total, 120000);
      await recordFrames(pageJ, "scrubbing the simulation's move slider (keyframes, then a run to the move)");
      await pageJ.screenshot({ path: path.join(artifacts, "11b-simulation-scrubbed.png") });
      const bt = back.panel.status;
      check("simulation job: the move slider gives the stock at that move",
        bt.removed_volume_mm3 < jt.removed_volume_mm3 && bt.in_background === true && back.jobs.on_page === jobs0.on_page,
        `move ${bt.moves_simulated} of ${bt.moves_total}: ${bt.removed_volume_mm3} mm³ after ${Date.now() - ts} ms`);
    }
    await pageJ.close();
  }

  // 10c. The native benchmark's 5-axis program, given to the tab through the page address
  // (`?view=…&set=benchmark:five-axis:N`: built in the worker from those numbers), on a
  // coarser grid than the benchmark's so the check is short: the run finishes in the
  // worker, its progress rises, and its numbers are the command line's for the same
  // program, cutter, block and pitch. (e2e/sim-bench.mjs measures the full 10 000 moves on
  // 512 × 512 rays.)
  {
    const TAB = "Cutting simulation";
    const pageB = await context.newPage();
    currentTab = "simulation";
    const q = `?view=${encodeURIComponent(TAB)}&set=${encodeURIComponent("benchmark:five-axis:1000")}&set=${encodeURIComponent("pitch:0.4")}`;
    await pageB.goto(url + q);
    const seen = [];
    const t0 = Date.now();
    let sb = null;
    // The page repaints a running job's progress once a second, and at once on input: the
    // mouse moves over the page as a user's would, so each look sees the latest progress
    // even when the job takes under a second.
    let wiggle = 0;
    while (Date.now() - t0 < 120000) {
      const s = await status(pageB).catch(() => null);
      const st = s && s.panel && s.panel.title === TAB ? s.panel.status : null;
      if (st && st.computing && (seen.length === 0 || seen[seen.length - 1] !== st.progress)) seen.push(st.progress);
      if (st && (st.stage === "done" || st.stage === "error")) { sb = st; break; }
      wiggle += 1;
      await pageB.mouse.move(900 + (wiggle % 2) * 4, 80).catch(() => {});
      await pageB.waitForTimeout(20);
    }
    const rising = seen.every((v, i) => i === 0 || v >= seen[i - 1]);
    check("benchmark program from the address: machined in the worker, progress rising",
      sb !== null && sb.error === null && sb.benchmark === "five-axis:1000" && sb.moves_simulated === 1000
        && sb.grid.nx === 128 && sb.in_background === true && rising && seen.length >= 1
        // Progress is repainted once a second: a job that ran longer must have shown it rise.
        && (seen.length >= 2 || sb.sim_ms < 1500),
      sb ? `${sb.moves_simulated} moves on ${sb.grid.nx}×${sb.grid.ny} rays, ${sb.ray_updates} ray updates in ${Math.round(sb.sim_ms)} ms, progress seen ${seen.map((v) => v.toFixed(2)).join(" ")}` : "no result");
    // The command line's numbers, if its binary is built (cargo builds it for the tests).
    // The newest of the debug and release binaries (a stale one may lack --benchmark).
    const bins = ["release", "debug"].map((d) => path.join(here, "..", "target", d, "interpolab")).filter((b) => fs.existsSync(b))
      .sort((a, b) => fs.statSync(b).mtimeMs - fs.statSync(a).mtimeMs);
    if (sb && bins.length > 0) {
      const { execFileSync } = await import("node:child_process");
      const out = JSON.parse(execFileSync(bins[0], ["simulate", "--benchmark", "five-axis:1000", "--cutter", "ball:3",
        "--stock", "0,0,0,51.2,51.2,20", "--pitch", "0.4"], { encoding: "utf8" }));
      // The removed volume (to 1e-6 mm³) and the moves are the same; the ray updates may
      // differ by a few in 10⁵: the joints come from trigonometry (inverse and forward
      // kinematics), whose last bits differ between the native libm and wasm's, and a ray
      // grazed at 1e-15 mm counts as an update on one side only.
      check("benchmark program: the browser's numbers are the command line's",
        Math.abs(out.ray_updates - sb.ray_updates) <= 1e-4 * out.ray_updates && out.removed_volume_mm3 === sb.removed_volume_mm3
          && out.moves === sb.moves_simulated && out.grid.nx === sb.grid.nx,
        `browser ${sb.ray_updates} updates, ${sb.removed_volume_mm3} mm³; command line ${out.ray_updates}, ${out.removed_volume_mm3} mm³`);
    } else {
      console.log("      (no target/*/interpolab binary: the comparison with the command line is skipped)");
    }
    await pageB.close();
  }

  // 11. Fillet end mill (seed 001): the default finishing part's iso-scallop paths, built
  // path by path over frames, drawn with the cutter at a contact point.
  {
    const TAB = "Fillet end mill (seed 001)";
    const pageF = await context.newPage();
    await pageF.goto(url);
    let sf = await waitFor(pageF, "the app for the fillet tab", settled);
    const tabF = sf.ui[TAB];
    currentTab = "fillet";
    await resetFrames(pageF);
    await pageF.mouse.click(tabF[0] + tabF[2] / 2, tabF[1] + tabF[3] / 2);
    sf = await waitFor(pageF, "the fillet paths", (s) => s.panel && s.panel.title === TAB && s.panel.status
      && s.panel.status.computing === false && s.panel.status.passes > 0, 180000);
    await recordFrames(pageF, "the fillet tab builds its paths");
    await pageF.waitForTimeout(500);
    const shotF = await pageF.screenshot({ path: path.join(artifacts, "12-fillet-end-mill.png") });
    const fs1 = sf.panel.status;
    check("fillet tab: the iso-scallop paths are built, the cutter's curvature above the surface's",
      fs1.error === null && fs1.passes > 0 && fs1.strip_mm.min > 0 && fs1.selected
        && fs1.selected.k_cutter_per_mm >= fs1.selected.k_surface_per_mm,
      `${fs1.passes} passes, ${fs1.length_mm.toFixed(1)} mm, strip ${fs1.strip_mm.min.toFixed(3)}–${fs1.strip_mm.max.toFixed(3)} mm, core ${Math.round(fs1.core_ms)} ms, longest step ${Math.round(fs1.longest_step_ms)} ms`);
    const vF = colourVariety(shotF, [420, 60, 900, 520]);
    check("fillet tab: the surface and paths are drawn (not blank)", vF > 40, `${vF} distinct colours in the view`);
    const sc = fs1.ui && fs1.ui.scallop_slider;
    if (sc) {
      await resetFrames(pageF);
      await dragSlider(pageF, sc);
      await waitFor(pageF, "the fillet paths at a new scallop height", (s) => s.panel.status.computing === false
        && s.panel.status.passes > 0 && s.panel.status.h_mm !== fs1.h_mm, 180000);
      await recordFrames(pageF, "dragging the fillet scallop slider");
    }
    // 12. From the fillet tab to the cutting simulation: "Simulate this program" hands its
    // paths over as the five-axis program through the machine, machined with the fillet
    // cutter and measured against the finish surface on a stock sized to the part.
    const sf2 = await waitFor(pageF, "the fillet paths before simulating", (s) => s.panel.status.computing === false
      && s.panel.status.passes > 0 && s.panel.status.ui && s.panel.status.ui.fillet_simulate, 180000);
    const fb = sf2.panel.status.ui.fillet_simulate;
    await resetFrames(pageF);
    await pageF.mouse.click(fb[0] + fb[2] / 2, fb[1] + fb[3] / 2);
    currentTab = "simulation";
    const sh = await waitFor(pageF, "the simulation of the fillet program", (s) => s.panel && s.panel.title === "Cutting simulation"
      && s.panel.status && s.panel.status.source === "finish" && s.panel.status.computing === false
      && (s.panel.status.stage === "done" || s.panel.status.stage === "error"), 300000);
    await recordFrames(pageF, "the simulation machines the fillet tab's program");
    await pageF.waitForTimeout(500);
    const shotH = await pageF.screenshot({ path: path.join(artifacts, "13-fillet-program-simulated.png") });
    const sth = sh.panel.status;
    check("fillet tab → simulation: its program is machined with its cutter against the finish surface",
      sth.error === null && sth.stage === "done" && sth.design === "finish surface" && sth.finish
        && sth.finish.passes === sf2.panel.status.passes && sth.moves_total > 0 && sth.scallop_um && sth.scallop_um.rays > 0,
      JSON.stringify({ finish: sth.finish, cutter: sth.cutter, grid: sth.grid, moves: sth.moves_total, scallop_um: sth.scallop_um,
        gouge: sth.gouge, sim_ms: Math.round(sth.sim_ms), slowest_frame_ms: sth.slowest_frame_ms }));
    const vH = colourVariety(shotH, [420, 60, 900, 520]);
    check("fillet program simulated: the machined part is drawn (not blank)", vH > 40, `${vH} distinct colours in the view`);
    await pageF.close();
  }

  // 11b. The fillet comparison table as background jobs: ten whole core runs, two at a time
  // in Web Workers, rows filled in as they finish while the view is orbited (a row takes
  // ~0.15 s natively now, so the page may see only one count between none and all ten).
  {
    const TAB = "Fillet end mill (seed 001)";
    const pageT = await context.newPage();
    await pageT.goto(url);
    let st = await waitFor(pageT, "the app for the fillet table", settled);
    const jobs0 = st.jobs;
    const tabT = st.ui[TAB];
    currentTab = "fillet";
    await pageT.mouse.click(tabT[0] + tabT[2] / 2, tabT[1] + tabT[3] / 2);
    st = await waitFor(pageT, "the fillet paths before the table", (s) => s.panel && s.panel.title === TAB && s.panel.status
      && s.panel.status.computing === false && s.panel.status.passes > 0, 180000);
    const tb = st.panel.status.ui.table_button;
    await resetFrames(pageT);
    const t0 = Date.now();
    await pageT.mouse.click(tb[0] + tb[2] / 2, tb[1] + tb[3] / 2);
    const seen = new Set();
    for (let i = 0; i < 400; i++) {
      await pageT.mouse.move(600, 400);
      await pageT.mouse.down();
      await pageT.mouse.move(640 + (i % 5) * 10, 420, { steps: 6 });
      await pageT.mouse.up();
      const now = await status(pageT);
      const p = now.panel.status;
      if (p.table_requested) seen.add(p.table_rows_done);
      if (p.table_requested && p.computing === false) break;
    }
    st = await waitFor(pageT, "the fillet comparison table", (s) => s.panel.status.table_requested
      && s.panel.status.computing === false, 300000);
    await recordFrames(pageT, "orbiting the view while the fillet table's rows compute");
    await pageT.screenshot({ path: path.join(artifacts, "12b-fillet-table.png") });
    const ft = st.panel.status;
    check("fillet table: its ten rows computed in Web Workers, arriving while the page drew",
      ft.table.length === 10 && ft.table.every((r) => r.passes > 0) && ft.table_in_background === true
        && st.jobs.background >= jobs0.background + 9 && st.jobs.on_page === jobs0.on_page
        && seen.size >= 2 && Math.min(...seen) < 10,
      `${ft.table.length} rows in ${Date.now() - t0} ms, row counts seen ${[...seen].join(",")}, jobs ${JSON.stringify(st.jobs)}`);
    await pageT.close();
  }

  // 11c. The fillet tab's picking: in "adds a start-curve point" mode three clicks on the
  // surface pick the start curve (the paths then start from it and go to both sides); in
  // "selects a CC point" mode a click on the paths moves the cutter to the nearest CC point.
  {
    const TAB = "Fillet end mill (seed 001)";
    const pageP = await context.newPage();
    await pageP.goto(url);
    let sp = await waitFor(pageP, "the app for the fillet picking", settled);
    const tabP = sp.ui[TAB];
    currentTab = "fillet";
    await pageP.mouse.click(tabP[0] + tabP[2] / 2, tabP[1] + tabP[3] / 2);
    sp = await waitFor(pageP, "the fillet paths before picking", (s) => s.panel && s.panel.title === TAB && s.panel.status
      && s.panel.status.computing === false && s.panel.status.passes > 0 && s.panel.status.ui
      && s.panel.status.ui.fillet_pick_mode && s.panel.status.ui.fillet_view, 180000);
    const firstPasses = sp.panel.status.passes;
    const pm = sp.panel.status.ui.fillet_pick_mode;
    await pageP.mouse.click(pm[0] + 8, pm[1] + pm[3] / 2);
    await waitFor(pageP, "the pick mode", (s) => s.panel.status.click_mode === "pick");
    const v = sp.panel.status.ui.fillet_view;
    const [cx, cy] = [v[0] + v[2] / 2, v[1] + v[3] / 2];
    const clicks = [[cx - 0.25 * v[2], cy + 0.05 * v[3]], [cx, cy - 0.03 * v[3]], [cx + 0.25 * v[2], cy + 0.02 * v[3]]];
    await resetFrames(pageP);
    for (const [i, [x, y]] of clicks.entries()) {
      await pageP.mouse.click(x, y);
      await waitFor(pageP, `picked point ${i + 1}`, (s) => s.panel.status.picked && s.panel.status.picked.length === i + 1, 20000);
      await pageP.waitForTimeout(700); // apart in time, so two clicks are not a double click
    }
    sp = await waitFor(pageP, "the paths from the picked curve", (s) => s.panel.status.computing === false
      && s.panel.status.start === "picked" && s.panel.status.passes > 0, 180000);
    await recordFrames(pageP, "picking the start curve and building its paths");
    await pageP.waitForTimeout(500);
    const shotP = await pageP.screenshot({ path: path.join(artifacts, "12c-fillet-picked-start.png") });
    const ps = sp.panel.status;
    check("fillet picking: three clicks on the surface start the paths from that curve, to both sides",
      ps.error === null && ps.picked.length === 3 && ps.second_side !== null && ps.second_side > 1 && ps.passes > 2,
      `picked ${JSON.stringify(ps.picked)}, ${ps.passes} passes (from the first edge: ${firstPasses}), second side from path ${ps.second_side}`);
    const sm = ps.ui.fillet_select_mode;
    await pageP.mouse.click(sm[0] + 8, sm[1] + sm[3] / 2);
    await waitFor(pageP, "the select mode", (s) => s.panel.status.click_mode === "select");
    const before = ps.selected;
    await pageP.mouse.click(cx + 0.1 * v[2], cy + 0.15 * v[3]);
    const ss = await waitFor(pageP, "a CC point selected by a click", (s) => typeof s.panel.status.last_click === "string"
      && s.panel.status.last_click.startsWith("selected"), 20000);
    await pageP.waitForTimeout(500);
    const shotS = await pageP.screenshot({ path: path.join(artifacts, "12d-fillet-clicked-cc-point.png") });
    const sel = ss.panel.status.selected;
    check("fillet picking: a click on the paths selects the CC point the cutter is drawn at",
      sel && (sel.path !== before.path || sel.node !== before.node),
      `${ss.panel.status.last_click} (before: path ${before.path}, node ${before.node})`);
    const vP = colourVariety(shotP, [420, 60, 900, 520]);
    const vS = colourVariety(shotS, [420, 60, 900, 520]);
    check("fillet picking: the view is drawn (not blank)", vP > 40 && vS > 40, `${vP}, ${vS} distinct colours`);
    await pageP.close();
  }
} catch (e) {
  failed = true;
  console.log(`FAIL  ${e.message}`);
}
const unexpected = consoleErrors.filter((t) => !/GPU stall due to ReadPixels/.test(t));
check("no console error", unexpected.length === 0, unexpected.slice(0, 5).join(" | "));
await browser.close();

// 10. WebGPU where the browser has it. These flags give headless Chromium a SwiftShader
// WebGPU adapter that really renders (with --enable-unsafe-webgpu alone it draws nothing);
// the checks above ran on WebGL2, wgpu's fallback.
try {
  const gpuBrowser = await chromium.launch({
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    args: [
      "--no-sandbox", "--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-vulkan=swiftshader",
      "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
      "--disable-component-update", "--disable-sync",
    ],
  });
  const gpuPage = await gpuBrowser.newPage({ viewport: { width: 1400, height: 900 } });
  const gpuErrors = [];
  gpuPage.on("console", (m) => { if (m.type() === "error") gpuErrors.push(m.text()); });
  await gpuPage.goto(url);
  const sg = await waitFor(gpuPage, "the first path on WebGPU", settled);
  const shotG = await gpuPage.screenshot({ path: path.join(artifacts, "10-webgpu.png") });
  const varietyG = colourVariety(shotG, [420, 60, 900, 520]);
  check("on WebGPU: the app chose the WebGPU backend and drew its first frame",
    sg.gpu_backend === "BrowserWebGpu" && varietyG > 40, `backend ${sg.gpu_backend}, ${varietyG} distinct colours`);
  check("on WebGPU: no console error", gpuErrors.length === 0, gpuErrors.slice(0, 3).join(" | "));
  await gpuBrowser.close();
} catch (e) {
  check("on WebGPU: the app runs", false, e.message);
}

if (frameReport.length > 0) {
  // Per tab: every gap of its recordings pooled is not kept, so the tab's figures are the
  // worst of its recordings (median and p99 of the recording with the highest p99).
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

const passed = results.filter((r) => r.ok).length;
const failedCount = results.length - passed + (failed ? 1 : 0);
console.log(`\ne2e: ${passed} passed, ${failedCount} failed (screenshots in e2e/artifacts/)`);
process.exit(failedCount === 0 ? 0 : 1);
