// The cutting simulation tab: the scene's crease program machined into a dexel stock and
// measured against the design, as a background job in a Web Worker, the move slider, and
// the native benchmark's program given through the page address (its numbers against the
// command line's).
import fs from "node:fs";
import path from "node:path";
import {
  VIEW, check, clickRect, dragSlider, drawnVariety, openSettled, recordFrames, repo, resetFrames, shotPath, status,
  waitFor,
} from "../harness.mjs";

const TAB = "Cutting simulation";
const doneRun = (s) => s.panel && s.panel.title === TAB && s.panel.status && s.panel.status.stage === "done" && s.panel.status.computing === false;

export const checks = [
  {
    name: "the crease program is machined move by move, measured and drawn; the move slider scrubs",
    run: async ({ context, url }) => {
      const { page, s } = await openSettled(context, url, "the app for the simulation tab");
      await resetFrames(page);
      await clickRect(page, s.ui[TAB]);
      const ss = await waitFor(page, "the cutting simulation", doneRun, 300000);
      await recordFrames(page, "the simulation tab machines the crease program", "simulation");
      const st = ss.panel.status;
      check("simulation tab: the crease program is machined, every move",
        st.error === null && st.moves_total > 0 && st.moves_simulated === st.moves_total && st.removed_volume_mm3 > 0
          && st.grid.nx <= 256 && st.grid.ny <= 256,
        `${st.moves_simulated}/${st.moves_total} moves on ${st.grid.nx}×${st.grid.ny} rays at ${st.grid.pitch_mm} mm, ${st.removed_volume_mm3} mm³ removed, slowest step ${st.slowest_frame_ms} ms`);
      check("simulation tab: scallops and gouges are measured against the design",
        st.scallop_um !== null && st.scallop_um.rays > 0, JSON.stringify({ scallop_um: st.scallop_um, gouge: st.gouge }));
      const vS = await drawnVariety(page, "11-cutting-simulation.png", VIEW, 40);
      check("simulation tab: the machined stock is drawn (not blank)", vS > 40, `${vS} distinct colours in the view`);
      // Scrub the move slider back: the stock is machined again up to that move.
      const ms = st.ui && st.ui.sim_move_slider;
      if (ms) {
        await resetFrames(page);
        // The rail is the slider's first 100 points (the rest is its text).
        await dragSlider(page, ms, 90, 50);
        await waitFor(page, "the stock at the scrubbed move", (s) => s.panel.status.computing === false
          && s.panel.status.moves_simulated !== st.moves_simulated, 300000);
        await recordFrames(page, "dragging the simulation's move slider", "simulation");
      }
      await page.close();
    },
  },
  {
    // The program is made, machined and measured in a Web Worker (the core's second wasm
    // module), the page only draws what comes back; the view is orbited while it computes
    // (frames recorded), and the move slider shows a keyframe at once, then the exact stock
    // from a run to that move.
    name: "the simulation runs as a background job in a Web Worker; the move slider gives the stock at that move",
    run: async ({ context, url }) => {
      const { page, s } = await openSettled(context, url, "the app for the simulation job");
      const jobs0 = s.jobs;
      await clickRect(page, s.ui[TAB]);
      await resetFrames(page);
      // Orbit the view (drag across it) while the worker machines.
      const t0 = Date.now();
      for (let i = 0; i < 6; i++) {
        await page.mouse.move(700, 400);
        await page.mouse.down();
        await page.mouse.move(760 + 10 * i, 430, { steps: 8 });
        await page.mouse.up();
        const now = await status(page);
        if (now.panel && now.panel.status && now.panel.status.stage === "done") break;
      }
      const sj = await waitFor(page, "the simulation job", doneRun, 300000);
      await recordFrames(page, "orbiting the view while the simulation job machines", "simulation");
      const jt = sj.panel.status;
      check("simulation job: machined and measured in a Web Worker, not on the page",
        jt.in_background === true && sj.jobs.background > jobs0.background && sj.jobs.on_page === jobs0.on_page
          && jt.moves_simulated === jt.moves_total && jt.scallop_um !== null,
        `${jt.moves_total} moves, ${jt.removed_volume_mm3} mm³ in ${Math.round(jt.sim_ms)} ms wall (${Date.now() - t0} ms to done), longest frame on it ${jt.slowest_frame_ms.toFixed(1)} ms, jobs ${JSON.stringify(sj.jobs)}`);
      const msj = jt.ui && jt.ui.sim_move_slider;
      if (msj) {
        await resetFrames(page);
        const ts = Date.now();
        await dragSlider(page, msj, 90, 30, 12);
        const back = await waitFor(page, "the exact stock at the scrubbed move", (s) => s.panel.status.computing === false
          && s.panel.status.stage === "done" && s.panel.status.moves_simulated < jt.moves_total, 300000);
        await recordFrames(page, "scrubbing the simulation's move slider (keyframes, then a run to the move)", "simulation");
        await page.screenshot({ path: shotPath("11b-simulation-scrubbed.png") });
        const bt = back.panel.status;
        check("simulation job: the move slider gives the stock at that move",
          bt.removed_volume_mm3 < jt.removed_volume_mm3 && bt.in_background === true && back.jobs.on_page === jobs0.on_page,
          `move ${bt.moves_simulated} of ${bt.moves_total}: ${bt.removed_volume_mm3} mm³ after ${Date.now() - ts} ms`);
      }
      await page.close();
    },
  },
  {
    // The native benchmark's 5-axis program, given to the tab through the page address
    // (`?view=…&set=benchmark:five-axis:N`: built in the worker from those numbers), on a
    // coarser grid than the benchmark's so the check is short: the run finishes in the
    // worker, its progress rises to 1, and its numbers are the command line's for the same
    // program, cutter, block and pitch. (e2e/sim-bench.mjs measures the full 10 000 moves
    // on 512 × 512 rays.)
    name: "the benchmark program from the address is machined in the worker, its progress rising",
    run: async ({ context, url, state }) => {
      const page = await context.newPage();
      const q = `?view=${encodeURIComponent(TAB)}&set=${encodeURIComponent("benchmark:five-axis:1000")}&set=${encodeURIComponent("pitch:0.4")}`;
      const t0 = Date.now();
      await page.goto(url + q);
      // The progress the page shows while the job runs, with when it was read (ms after the
      // navigation). How many readings there are depends on the machine's load, not on the
      // job: the page repaints a running job's progress once a second and at once on input
      // (the mouse moves over the page as a user's would), and most of a short run's time
      // (`sim_ms`, from the request) can be the worker starting and compiling its wasm,
      // during which the progress is 0. So the order of the readings is asserted, never
      // their number: each within [0, 1], none lower than the one before, and 1 when done.
      const seen = [];
      let sb = null;
      let wiggle = 0;
      while (Date.now() - t0 < 300000) {
        const s = await status(page).catch(() => null);
        const st = s && s.panel && s.panel.title === TAB ? s.panel.status : null;
        if (st && st.computing && (seen.length === 0 || seen[seen.length - 1].p !== st.progress)) seen.push({ p: st.progress, ms: Date.now() - t0 });
        if (st && (st.stage === "done" || st.stage === "error")) { sb = st; break; }
        wiggle += 1;
        await page.mouse.move(900 + (wiggle % 2) * 4, 80).catch(() => {});
        await page.waitForTimeout(20);
      }
      const p = seen.map((r) => r.p);
      const rising = p.every((v, i) => v >= 0 && v <= 1 && (i === 0 || v >= p[i - 1]));
      check("benchmark program from the address: machined in the worker, progress rising",
        sb !== null && sb.error === null && sb.benchmark === "five-axis:1000" && sb.moves_simulated === 1000
          && sb.grid.nx === 128 && sb.in_background === true && rising && sb.progress === 1,
        sb ? `${sb.moves_simulated} moves on ${sb.grid.nx}×${sb.grid.ny} rays, ${sb.ray_updates} ray updates in ${Math.round(sb.sim_ms)} ms, progress seen ${seen.map((r) => `${r.p.toFixed(2)} (${r.ms} ms)`).join(" ") || "none"}, then ${sb.progress}` : "no result");
      state.sb = sb;
      await page.close();
    },
  },
  {
    name: "the benchmark program: the browser's numbers are the command line's",
    run: async ({ state }) => {
      const { sb } = state;
      // The command line's numbers, if its binary is built (cargo builds it for the tests).
      // The newest of the debug and release binaries (a stale one may lack --benchmark).
      const bins = ["release", "debug"].map((d) => path.join(repo, "target", d, "interpolab")).filter((b) => fs.existsSync(b))
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
    },
  },
];
