// The "Your program" tab in the release web app, in Debian's headless Chromium, as a user meets
// it: a real multi-tool program opened with its tool table (and its subroutine file), the path
// drawn, its reports listed, colours by tool and by nonlinear error, Simulate with progress in
// the worker, the stock drawn; a program whose shank and rapids meet the stock, its crashes
// listed and marked in red; then LinuxCNC's impeller demo (5-axis, TCP) and a generated
// 180 000-line program with the page's frame gaps recorded while it is read and shown.
// Usage: node e2e/userprog.mjs http://127.0.0.1:PORT/   (screenshots in e2e/artifacts/)
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { PNG } from "pngjs";
import { openBrowser } from "./browser.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const url = process.argv[2] ?? "http://127.0.0.1:8765/";
const artifacts = path.join(here, "artifacts");
fs.mkdirSync(artifacts, { recursive: true });
const TAB = "Your program";
const DEMOS = "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/vismach/5axis/table-rotary-tilting";

const results = [];
function check(name, ok, detail = "") {
  results.push({ name, ok });
  console.log(`${ok ? "ok  " : "FAIL"}  ${name}${detail ? " — " + detail : ""}`);
}
async function status(page) {
  const text = await page.locator("#app-status").textContent();
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
  throw new Error(`timed out waiting for ${what}; last status: ${JSON.stringify(last?.panel?.status ?? last)}`);
}
function colourVariety(pngBuffer, region) {
  const png = PNG.sync.read(pngBuffer);
  const seen = new Set();
  const [x0, y0, w, h] = region.map(Math.round);
  for (let y = Math.max(0, y0); y < Math.min(png.height, y0 + h); y += 2) {
    for (let x = Math.max(0, x0); x < Math.min(png.width, x0 + w); x += 2) {
      const i = (png.width * y + x) << 2;
      seen.add((png.data[i] >> 3) << 10 | (png.data[i + 1] >> 3) << 5 | (png.data[i + 2] >> 3));
    }
  }
  return seen.size;
}
const tabReady = (s) => s.panel && s.panel.title === TAB && s.panel.status;
const read = (s) => tabReady(s) && s.panel.status.blocks != null && !s.panel.status.computing;
async function frameGaps(page) {
  const gaps = await page.evaluate(() => window.__frameGaps.splice(0));
  const sorted = [...gaps].sort((a, b) => a - b);
  const q = (f) => sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(f * sorted.length))] : NaN;
  return { frames: gaps.length, median: q(0.5), p99: q(0.99), longest: sorted[sorted.length - 1] ?? NaN };
}
async function openFile(page, name, text) {
  await page.setInputFiles("#scene-file", { name, mimeType: "text/plain", buffer: Buffer.from(text) });
}
async function clickKey(page, key) {
  const r = (await status(page)).panel.status.ui[key];
  await page.mouse.click(r[0] + r[2] / 2, r[1] + r[3] / 2);
}

// A two-tool pocket-and-engrave job with a tool table, as a CAM post writes it, and a
// subroutine file it calls.
const PROGRAM = [
  "(two tools: a 6 mm end mill clears a pocket, a 90 degree V engraves two grooves)",
  "G21 G90 G17 G94", "G0 Z100", "T1 M6", "G0 G43 H1 Z30 S12000 M3", "G0 X5 Y5", "G0 Z2",
  "G1 Z-2 F300", "G1 X35 F900", "G1 Y25", "G1 X5", "G1 Y5", "G1 X35 Y10", "G1 X5 Y15", "G1 X35 Y20",
  "G2 X35 Y5 I0 J-7.5", "G0 Z100", "T2 M6", "G0 G43 H2 Z30", "o<engrave> call [32]", "o<engrave> call [36]",
  "G0 Z30", "M30",
].join("\n") + "\n";
const SUB = ["o<engrave> sub", "G0 X0 Y#1", "G0 Z2", "G1 Z-1.2 F400", "G1 X40", "G0 Z5", "o<engrave> endsub"].join("\n") + "\n";
const TABLE = "T1 P1 Z40 D6 ;flat 6 mm end mill\nT2 P2 Z52.5 D6 ;v90 engraver\n";
// A slot cut 15 mm deep in one pass with a 6 mm end mill of 10 mm flutes (its table remark
// gives them): the shank rubs 5 mm of stock on lines 6 and 7, the G0s of lines 8 and 10 go
// through stock.
const DEEP = [
  "(a slot 15 mm deep in one pass: too deep for 10 mm flutes)", "G21 G90", "T1 M6", "G0 X0 Y0 Z5",
  "G1 Z-15 F300", "G1 X40", "G1 Y20", "G0 Z5", "G0 X20 Y10", "G0 Z-2", "G1 X30 F300", "G0 Z5", "M30",
].join("\n") + "\n";
const DEEP_TABLE = "T1 P1 D6 ;flat flute=10 6 mm end mill, 10 mm flutes\n";

const { browser, context } = await openBrowser();
const consoleErrors = [];
context.on("console", (m) => { if (m.type() === "error") consoleErrors.push(m.text()); });
let failed = false;
try {
  const page = await context.newPage();
  await page.goto(url);
  const s0 = await waitFor(page, "the first frame", (s) => s.frames >= 3 && s.ui && s.ui[TAB]);
  const tab = s0.ui[TAB];
  await page.mouse.click(tab[0] + tab[2] / 2, tab[1] + tab[3] / 2);
  await waitFor(page, "the tab", tabReady);
  await openFile(page, "pocket.tbl", TABLE);
  await openFile(page, "engrave.ngc", SUB);
  await openFile(page, "pocket-engrave.ngc", PROGRAM);
  let s = await waitFor(page, "the program read", (s) => read(s) && s.panel.status.program === "pocket-engrave.ngc");
  let st = s.panel.status;
  check("a multi-tool program opens with its tool table and subroutine file",
    st.blocks > 15 && st.tools.length === 2 && st.tool_table === "pocket.tbl" && st.subroutines[0] === "engrave.ngc",
    `${st.blocks} blocks, tools ${st.tools.map((t) => `T${t.number} ${t.cutter}`).join(", ")}`);
  await page.waitForTimeout(300);
  let shot = await page.screenshot({ path: path.join(artifacts, "userprog-1-path.png") });
  const view = st.ui.path_view;
  check("its path is drawn (the view is not blank)", colourVariety(shot, view) > 8 && st.drawn_segments > 10,
    `${colourVariety(shot, view)} colours, ${st.drawn_segments} segments`);
  // Colour by tool; then simulate with its tools in the worker.
  await page.evaluate(() => { window.__frameGaps.length = 0; });
  await clickKey(page, "simulate");
  s = await waitFor(page, "the stock machined", (s) => tabReady(s) && s.panel.status.removed_mm3 && !s.panel.status.computing);
  st = s.panel.status;
  const g = await frameGaps(page);
  check("Simulate machines it with both tools, no rapid in the material", st.removed_mm3.length === 2 && st.removed_mm3.every((v) => v > 1) && st.rapid_cuts === 0,
    `removed ${st.removed_mm3.map((v) => v.toFixed(1)).join(" + ")} mm³ on ${st.stock_rays} rays in ${Math.round(st.run_ms)} ms; frames: median ${g.median?.toFixed(1)} ms, longest ${g.longest?.toFixed(1)} ms`);
  await page.waitForTimeout(300);
  shot = await page.screenshot({ path: path.join(artifacts, "userprog-2-simulated.png") });
  check("the stock is drawn by tool", colourVariety(shot, st.ui.stock_map) > 8, `${colourVariety(shot, st.ui.stock_map)} colours`);

  // Crashes: the shank below its flutes' reach and rapids through the stock, listed by line
  // and marked in red; a click on the first row picks its line.
  await openFile(page, "deep.tbl", DEEP_TABLE);
  await openFile(page, "deep-slot.ngc", DEEP);
  s = await waitFor(page, "the deep slot read", (s) => read(s) && s.panel.status.program === "deep-slot.ngc");
  check("the table's remark gives the tool's flutes", s.panel.status.tools[0].body.startsWith("flutes 10 mm"),
    s.panel.status.tools[0].body);
  await clickKey(page, "simulate");
  s = await waitFor(page, "the deep slot machined", (s) => tabReady(s) && s.panel.status.crashes && !s.panel.status.computing);
  st = s.panel.status;
  const c = st.crashes;
  check("its crashes are found at their lines, the shank's 5 mm deep",
    c.first && c.first.line === 6 && c.first.kind === "shank" && Math.abs(c.first.depth_mm - 5) < 0.05 && c.by_kind.rapid >= 1
      && st.drawn_crash_marks === c.listed,
    c.summary);
  await clickKey(page, "first_crash");
  s = await waitFor(page, "a crash picked", (s) => tabReady(s) && s.panel.status.crashes?.picked, 10000);
  check("a click on a crash's row picks its line", s.panel.status.selected_line === 6, `line ${s.panel.status.selected_line}`);
  await page.waitForTimeout(300);
  shot = await page.screenshot({ path: path.join(artifacts, "userprog-4-crashes.png") });
  // Red marks in the 3D view: pixels of the crash colour (255, 40, 40) where the path is drawn.
  const red = (() => {
    const png = PNG.sync.read(shot);
    const [x0, y0, w, h] = st.ui.path_view.map(Math.round);
    let n = 0;
    for (let y = Math.max(0, y0); y < Math.min(png.height, y0 + h); y++) {
      for (let x = Math.max(0, x0); x < Math.min(png.width, x0 + w); x++) {
        const i = (png.width * y + x) << 2;
        if (png.data[i] > 230 && png.data[i + 1] < 70 && png.data[i + 2] < 70) n++;
      }
    }
    return n;
  })();
  check("the crashes are marked in red in the view", red > 20 * c.listed, `${red} red pixels for ${c.listed} crash(es)`);

  // LinuxCNC's impeller: 5-axis under TCP, named by its own comment; coloured by nonlinear error.
  if (fs.existsSync(path.join(DEMOS, "demos/impeller-7bl-xyzac.ngc"))) {
    await openFile(page, "xyzac-trt.tbl", fs.readFileSync(path.join(DEMOS, "xyzac-trt.tbl"), "utf8"));
    await openFile(page, "impeller-7bl-xyzac.ngc", fs.readFileSync(path.join(DEMOS, "demos/impeller-7bl-xyzac.ngc"), "utf8"));
    s = await waitFor(page, "the impeller read", (s) => read(s) && s.panel.status.program === "impeller-7bl-xyzac.ngc");
    st = s.panel.status;
    check("LinuxCNC's impeller is read through its machine with its nonlinear error per block",
      st.machine === "table-ac" && st.blocks === 4492 && st.worst_error && st.over_tolerance > 0,
      `machine ${st.machine}, ${st.blocks} blocks, worst ${st.worst_error?.mm?.toFixed(4)} mm at line ${st.worst_error?.line}, ${st.over_tolerance} over ${st.tol_mm} mm`);
    // Colour by error: pick "nonlinear error" in the combo box through the status' option route.
    await page.goto(url + `?view=${encodeURIComponent(TAB)}&set=colour:error`).catch(() => {});
  }
  // The page after an address with options: the colour option reaches the tab; load the
  // impeller again in this page and show it coloured by its error.
  if (fs.existsSync(path.join(DEMOS, "demos/impeller-7bl-xyzac.ngc"))) {
    await waitFor(page, "the tab from the address", tabReady);
    await openFile(page, "impeller-7bl-xyzac.ngc", fs.readFileSync(path.join(DEMOS, "demos/impeller-7bl-xyzac.ngc"), "utf8"));
    s = await waitFor(page, "the impeller read again", (s) => read(s) && s.panel.status.program === "impeller-7bl-xyzac.ngc");
    st = s.panel.status;
    await page.waitForTimeout(300);
    shot = await page.screenshot({ path: path.join(artifacts, "userprog-3-impeller-error.png") });
    check("the impeller is drawn coloured by nonlinear error", st.colour === "error" && colourVariety(shot, st.ui.path_view) > 8,
      `${colourVariety(shot, st.ui.path_view)} colours, ${st.drawn_segments} segments`);
    // A click on the first report shows its line.
    await clickKey(page, "first_message");
    s = await waitFor(page, "a line picked", (s) => tabReady(s) && s.panel.status.selected_line != null, 10000);
    check("a report's line is picked by a click", s.panel.status.selected_line > 0, `line ${s.panel.status.selected_line}`);
  }

  // A generated 180 000-line program: read in the worker, drawn thinned; the page's frames.
  // Made in the page and given to the file input as a File, as a file picked from a disk is:
  // handed over by the test driver instead (setInputFiles), its 5 MB crossed the driver's
  // protocol on the page's thread, one frame of about half a second that no user meets.
  await page.evaluate(() => {
    const lines = ["G21 G90 G17", "T1 M6", "G0 Z10", "G0 X0 Y0", "G1 Z-1 F2000"];
    for (let k = 0; lines.length < 180000; k++) {
      const y = Math.floor(k / 400) * 0.25;
      const i = k % 400;
      const x = (Math.floor(k / 400) % 2 === 0 ? i : 399 - i) * 0.25;
      lines.push(`X${x.toFixed(3)} Y${y.toFixed(3)} Z${(-1 - 0.8 * Math.sin(x / 9) * Math.cos(y / 7)).toFixed(4)}`);
    }
    lines.push("G0 Z10", "M30");
    window.__big = new File([lines.join("\n") + "\n"], "raster-180k.ngc", { type: "text/plain" });
  });
  await page.waitForTimeout(300);
  await page.evaluate(() => { window.__frameGaps.length = 0; });
  const t0 = Date.now();
  await page.evaluate(() => {
    const input = document.getElementById("scene-file");
    const dt = new DataTransfer();
    dt.items.add(window.__big);
    input.files = dt.files;
    input.dispatchEvent(new Event("change"));
  });
  s = await waitFor(page, "the big program read", (s) => read(s) && s.panel.status.program === "raster-180k.ngc", 300000);
  st = s.panel.status;
  const readMs = Date.now() - t0;
  const gRead = await frameGaps(page);
  // Turn the view for a while as a hand would, then let it rest.
  const v = st.ui.path_view;
  await page.mouse.move(v[0] + v[2] / 2, v[1] + v[3] / 2);
  await page.mouse.down();
  await page.mouse.move(v[0] + v[2] / 2 + 160, v[1] + v[3] / 2 + 40, { steps: 40 });
  await page.mouse.up();
  const gTurn = await frameGaps(page);
  await page.waitForTimeout(500);
  s = await status(page);
  shot = await page.screenshot({ path: path.join(artifacts, "userprog-4-180k.png") });
  const f = (g) => `${g.frames} frames, median ${g.median?.toFixed(1)} ms, p99 ${g.p99?.toFixed(1)} ms, longest ${g.longest?.toFixed(1)} ms`;
  check("a 180 000-line program is read and drawn", st.blocks > 179000 && s.panel.status.drawn_segments > 1000,
    `${st.lines} lines, ${st.blocks} blocks, ${s.panel.status.drawn_segments} segments drawn at rest, read in ${readMs} ms; while reading: ${f(gRead)}; while turning: ${f(gTurn)} (load ${os.loadavg()[0].toFixed(1)})`);
  check("no console error", consoleErrors.length === 0, consoleErrors.slice(0, 3).join(" | "));
} catch (e) {
  console.log(`FAIL  ${e.message}`);
  failed = true;
} finally {
  await browser.close();
}
const bad = results.filter((r) => !r.ok).length;
console.log(`${results.length - bad} of ${results.length} checks passed`);
process.exit(failed || bad > 0 ? 1 : 0);
