// The NURBS & G-code tab: the tab draws, its comparison is computed (in Web
// Workers), a program downloaded from it and loaded back is drawn and measured, a malformed
// one is refused with its line, the tolerance slider.
import fs from "node:fs";
import { PNG } from "pngjs";
import {
  base64url, check, clickRect, clickUntil, colourVariety, dragSlider, readText, recordFrames, resetFrames,
  screenshotUntil, shotPath, status, waitFor, settled,
} from "../harness.mjs";

const TAB = "NURBS & G-code";
const done = (s) => s.panel && s.panel.title === TAB && s.panel.status && s.panel.status.done;

export const checks = [
  {
    name: "the tab draws its view and compares the G01, G02/G03 and G06.2 programs",
    run: async ({ context, url, state }) => {
      const page = await context.newPage();
      await page.goto(url + "#scene=" + base64url(readText("examples", "torus-plane.json")));
      let sn = await waitFor(page, "the torus crease", settled);
      await resetFrames(page);
      await clickRect(page, sn.ui[TAB]);
      const tn = Date.now();
      sn = await waitFor(page, "the NURBS panel's comparison", done);
      await recordFrames(page, "the NURBS tab computes its comparison", "nurbs");
      const st = sn.panel.status;
      const v = st.ui.view;
      const { value: varietyN } = await screenshotUntil(page, "nurbs-1-panel.png", (shot) => colourVariety(shot, v), (n) => n > 40);
      check("NURBS panel draws its 3D view (not blank)", varietyN > 40, `${varietyN} distinct colours in the view`);
      const blocks = st.rows.map((r) => `${r.kind} ${r.path_blocks}`).join(", ");
      check("NURBS panel compares the G01, G02/G03 and G06.2 programs", st.status_ok && st.rows.length === 3
        && st.rows.every((r) => r.fresh && r.path_blocks > 0 && r.deviation_mm <= st.tol_mm) && st.realtime.length === 3,
        `${blocks} path blocks at ${st.tol_mm} mm, in ${Date.now() - tn} ms`);
      const times = st.rows.map((r) => `${r.kind} ${r.time_s?.toFixed(3)} s`).join(", ");
      check("NURBS panel times each program on its machine", st.machine && st.rows.every((r) => r.time_machine === st.machine
        && Number.isFinite(r.time_s) && r.time_s > 0 && r.feed_s > 0 && r.feed_s <= r.time_s),
        `${times} on ${st.machine}`);
      Object.assign(state, { page, st });
    },
  },
  {
    name: "a downloaded program loads back with the table's deviation and is drawn over the design",
    run: async ({ state }) => {
      const { page, st } = state;
      const v = st.ui.view;
      const rect = (key) => (s) => s.panel?.status?.ui?.[key];
      // Download the G01 program, then open the downloaded file: it is drawn over the design
      // and its deviation is the one the table reports.
      await clickUntil(page, "the G01 program shown", rect("G01"), (s) => s.panel.status.program === "g01");
      const downloaded = page.waitForEvent("download", { timeout: 120000 });
      await clickUntil(page, "the download", rect("download"), (s) => (s.panel.status.downloaded ?? "").endsWith("-g01.nc"));
      const download = await downloaded;
      const file = shotPath(download.suggestedFilename());
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
      const before = yellow(await page.screenshot());
      await page.setInputFiles("#scene-file", { name: download.suggestedFilename(), mimeType: "text/plain", buffer: fs.readFileSync(file) });
      const sn = await waitFor(page, "the loaded program's deviation", (s) => done(s) && s.panel.status.loaded?.deviation_mm != null);
      const loaded = sn.panel.status.loaded;
      const { value: after } = await screenshotUntil(page, "nurbs-2-loaded-program.png", yellow, (n) => n > before + 200);
      check("a downloaded program loads back with the table's deviation",
        download.suggestedFilename().endsWith(".nc") && loaded.error === null
          && Math.abs(loaded.deviation_mm - st.rows[0].deviation_mm) < 1e-9,
        `${loaded.name}: ${(loaded.deviation_mm * 1000).toFixed(3)} µm (table ${(st.rows[0].deviation_mm * 1000).toFixed(3)} µm), worst at line ${loaded.deviation_line}`);
      check("… and is drawn over the design", sn.panel.status.worst_px !== null && after > before + 200,
        `${after} yellow pixels (${before} before), worst-deviation marker at ${sn.panel.status.worst_px.map(Math.round)}`);
    },
  },
  {
    name: "a malformed G-code file shows the line and the fix",
    run: async ({ state }) => {
      const { page } = state;
      // An arc with neither centre nor radius: no controller can follow it.
      const bad = "%\nG21 G90\nG00 X0 Y0 Z5\nG02 X10 Y0 F500\nM30\n%\n";
      await page.setInputFiles("#scene-file", { name: "bad.ngc", mimeType: "text/plain", buffer: Buffer.from(bad) });
      const sn = await waitFor(page, "the malformed program's error", (s) => s.error.includes("bad.ngc"));
      await page.screenshot({ path: shotPath("nurbs-3-bad-program.png") });
      check("a malformed G-code file shows the line and the fix", sn.error.includes("line 4") && sn.error.includes("radius R")
        && sn.panel.status.loaded.error.includes("line 4"), sn.error);
    },
  },
  {
    name: "the comparison follows the tolerance slider, its programs written in Web Workers",
    run: async ({ state }) => {
      const { page, st } = state;
      // Drag the tolerance slider: the three programs are written again (in Web Workers).
      await resetFrames(page);
      const td = Date.now();
      await dragSlider(page, (await status(page)).panel.status.ui.tolerance_slider);
      const sd = await waitFor(page, "the comparison at a new tolerance", (s) => done(s) && s.panel.status.tol_mm !== st.tol_mm);
      await recordFrames(page, "dragging the NURBS tolerance slider", "nurbs");
      check("NURBS panel: the comparison follows the tolerance slider", sd.panel.status.rows.length === 3
        && sd.panel.status.rows.every((r) => r.fresh && r.deviation_mm <= sd.panel.status.tol_mm),
        `E ${st.tol_mm} → ${sd.panel.status.tol_mm.toFixed(4)} mm, recomputed in ${Date.now() - td} ms`);
      check("NURBS panel: its programs are written in Web Workers, not on the page",
        sd.jobs.background >= 6 && sd.jobs.on_page === 0, JSON.stringify(sd.jobs));
      await page.close();
    },
  },
];
