// The fillet end mill tab: the default finishing part's iso-scallop paths, built
// path by path over frames and drawn with the cutter at a contact point; its program through
// the cutting simulation; the comparison table as background jobs; picking on the surface.
import {
  VIEW, check, clickRect, colourVariety, dragSlider, drawnVariety, openSettled, recordFrames, resetFrames,
  screenshotUntil, shotPath, status, waitFor,
} from "../harness.mjs";

const TAB = "Fillet end mill";
const pathsDone = (s) => s.panel && s.panel.title === TAB && s.panel.status && s.panel.status.computing === false && s.panel.status.passes > 0;

export const checks = [
  {
    name: "the iso-scallop paths are built and drawn, the cutter's curvature above the surface's; the scallop slider rebuilds them",
    run: async ({ context, url, state }) => {
      const { page, s } = await openSettled(context, url, "the app for the fillet tab");
      await resetFrames(page);
      await clickRect(page, s.ui[TAB]);
      const sf = await waitFor(page, "the fillet paths", pathsDone, 300000);
      await recordFrames(page, "the fillet tab builds its paths", "fillet");
      const fs1 = sf.panel.status;
      check("fillet tab: the iso-scallop paths are built, the cutter's curvature above the surface's",
        fs1.error === null && fs1.passes > 0 && fs1.strip_mm.min > 0 && fs1.selected
          && fs1.selected.k_cutter_per_mm >= fs1.selected.k_surface_per_mm,
        `${fs1.passes} passes, ${fs1.length_mm.toFixed(1)} mm, strip ${fs1.strip_mm.min.toFixed(3)}–${fs1.strip_mm.max.toFixed(3)} mm, core ${Math.round(fs1.core_ms)} ms, longest step ${Math.round(fs1.longest_step_ms)} ms`);
      const vF = await drawnVariety(page, "12-fillet-end-mill.png", VIEW, 40);
      check("fillet tab: the surface and paths are drawn (not blank)", vF > 40, `${vF} distinct colours in the view`);
      const sc = fs1.ui && fs1.ui.scallop_slider;
      if (sc) {
        await resetFrames(page);
        await dragSlider(page, sc);
        await waitFor(page, "the fillet paths at a new scallop height", (s) => s.panel.status.computing === false
          && s.panel.status.passes > 0 && s.panel.status.h_mm !== fs1.h_mm, 300000);
        await recordFrames(page, "dragging the fillet scallop slider", "fillet");
      }
      state.page = page;
    },
  },
  {
    // "Simulate this program" hands the paths over as the five-axis program through the
    // machine, machined with the fillet cutter and measured against the finish surface on a
    // stock sized to the part.
    name: "its program is machined in the cutting simulation with its cutter against the finish surface",
    run: async ({ state }) => {
      const { page } = state;
      const sf2 = await waitFor(page, "the fillet paths before simulating", (s) => s.panel.status.computing === false
        && s.panel.status.passes > 0 && s.panel.status.ui && s.panel.status.ui.fillet_simulate, 300000);
      await resetFrames(page);
      await clickRect(page, sf2.panel.status.ui.fillet_simulate);
      const sh = await waitFor(page, "the simulation of the fillet program", (s) => s.panel && s.panel.title === "Cutting simulation"
        && s.panel.status && s.panel.status.source === "finish" && s.panel.status.computing === false
        && (s.panel.status.stage === "done" || s.panel.status.stage === "error"), 600000);
      await recordFrames(page, "the simulation machines the fillet tab's program", "simulation");
      const sth = sh.panel.status;
      check("fillet tab → simulation: its program is machined with its cutter against the finish surface",
        sth.error === null && sth.stage === "done" && sth.design === "finish surface" && sth.finish
          && sth.finish.passes === sf2.panel.status.passes && sth.moves_total > 0 && sth.scallop_um && sth.scallop_um.rays > 0,
        JSON.stringify({ finish: sth.finish, cutter: sth.cutter, grid: sth.grid, moves: sth.moves_total, scallop_um: sth.scallop_um,
          gouge: sth.gouge, sim_ms: Math.round(sth.sim_ms), slowest_frame_ms: sth.slowest_frame_ms }));
      const vH = await drawnVariety(page, "13-fillet-program-simulated.png", VIEW, 40);
      check("fillet program simulated: the machined part is drawn (not blank)", vH > 40, `${vH} distinct colours in the view`);
      await page.close();
    },
  },
  {
    // Ten whole core runs, in Web Workers (as many at once as the machine has cores less
    // one), rows filled in as they finish while the view is orbited.
    name: "the comparison table's ten rows are computed in Web Workers, arriving while the page draws",
    run: async ({ context, url }) => {
      const { page, s } = await openSettled(context, url, "the app for the fillet table");
      const jobs0 = s.jobs;
      await clickRect(page, s.ui[TAB]);
      const sp = await waitFor(page, "the fillet paths before the table", pathsDone, 300000);
      const f0 = sp.frames;
      await resetFrames(page);
      const t0 = Date.now();
      await clickRect(page, sp.panel.status.ui.table_button);
      // Rows done, in the order the page showed them while the table computed. How many
      // distinct counts a look sees depends on the machine's load (a row takes ~0.15 s
      // natively; under load the page may see none between the request and all ten), so
      // the order is asserted, not the number of readings.
      const seen = [];
      let last = null;
      for (let i = 0; i < 400; i++) {
        await page.mouse.move(600, 400);
        await page.mouse.down();
        await page.mouse.move(640 + (i % 5) * 10, 420, { steps: 6 });
        await page.mouse.up();
        const now = await status(page);
        const p = now.panel.status;
        if (p.table_requested && p.computing) seen.push(p.table_rows_done);
        if (p.table_requested && p.computing === false) { last = now; break; }
      }
      const st = last ?? await waitFor(page, "the fillet comparison table", (s) => s.panel.status.table_requested
        && s.panel.status.computing === false, 600000);
      await recordFrames(page, "orbiting the view while the fillet table's rows compute", "fillet");
      await page.screenshot({ path: shotPath("12b-fillet-table.png") });
      const ft = st.panel.status;
      const ordered = seen.every((n, i) => n < 10 && (i === 0 || n >= seen[i - 1]));
      check("fillet table: its ten rows computed in Web Workers, arriving while the page drew",
        ft.table.length === 10 && ft.table.every((r) => r.passes > 0) && ft.table_in_background === true
          && st.jobs.background >= jobs0.background + 9 && st.jobs.on_page === jobs0.on_page
          && ordered && st.frames > f0,
        `${ft.table.length} rows in ${Date.now() - t0} ms, row counts seen while computing ${seen.join(",") || "none"}, frames ${f0} → ${st.frames}, jobs ${JSON.stringify(st.jobs)}`);
      await page.close();
    },
  },
  {
    // In "adds a start-curve point" mode three clicks on the surface pick the start curve
    // (the paths then start from it and go to both sides); in "selects a CC point" mode a
    // click on the paths moves the cutter to the nearest CC point.
    name: "picking: three clicks start the paths from a curve, a click on the paths selects a CC point",
    run: async ({ context, url }) => {
      const { page, s } = await openSettled(context, url, "the app for the fillet picking");
      await clickRect(page, s.ui[TAB]);
      let sp = await waitFor(page, "the fillet paths before picking", (s) => pathsDone(s) && s.panel.status.ui
        && s.panel.status.ui.fillet_pick_mode && s.panel.status.ui.fillet_view, 300000);
      const firstPasses = sp.panel.status.passes;
      const pm = sp.panel.status.ui.fillet_pick_mode;
      await page.mouse.click(pm[0] + 8, pm[1] + pm[3] / 2);
      await waitFor(page, "the pick mode", (s) => s.panel.status.click_mode === "pick");
      const v = sp.panel.status.ui.fillet_view;
      const [cx, cy] = [v[0] + v[2] / 2, v[1] + v[3] / 2];
      const clicks = [[cx - 0.25 * v[2], cy + 0.05 * v[3]], [cx, cy - 0.03 * v[3]], [cx + 0.25 * v[2], cy + 0.02 * v[3]]];
      await resetFrames(page);
      for (const [i, [x, y]] of clicks.entries()) {
        await page.mouse.click(x, y);
        await waitFor(page, `picked point ${i + 1}`, (s) => s.panel.status.picked && s.panel.status.picked.length === i + 1);
        // At least this far apart, so two clicks are not a double click (a load only
        // lengthens the gap).
        await page.waitForTimeout(700);
      }
      sp = await waitFor(page, "the paths from the picked curve", (s) => s.panel.status.computing === false
        && s.panel.status.start === "picked" && s.panel.status.passes > 0, 300000);
      await recordFrames(page, "picking the start curve and building its paths", "fillet");
      const { value: vP } = await screenshotUntil(page, "12c-fillet-picked-start.png", (shot) => colourVariety(shot, VIEW), (n) => n > 40);
      const ps = sp.panel.status;
      check("fillet picking: three clicks on the surface start the paths from that curve, to both sides",
        ps.error === null && ps.picked.length === 3 && ps.second_side !== null && ps.second_side > 1 && ps.passes > 2,
        `picked ${JSON.stringify(ps.picked)}, ${ps.passes} passes (from the first edge: ${firstPasses}), second side from path ${ps.second_side}`);
      const sm = ps.ui.fillet_select_mode;
      await page.mouse.click(sm[0] + 8, sm[1] + sm[3] / 2);
      await waitFor(page, "the select mode", (s) => s.panel.status.click_mode === "select");
      const before = ps.selected;
      await page.mouse.click(cx + 0.1 * v[2], cy + 0.15 * v[3]);
      const ss = await waitFor(page, "a CC point selected by a click", (s) => typeof s.panel.status.last_click === "string"
        && s.panel.status.last_click.startsWith("selected"));
      const { value: vS } = await screenshotUntil(page, "12d-fillet-clicked-cc-point.png", (shot) => colourVariety(shot, VIEW), (n) => n > 40);
      const sel = ss.panel.status.selected;
      check("fillet picking: a click on the paths selects the CC point the cutter is drawn at",
        sel && (sel.path !== before.path || sel.node !== before.node),
        `${ss.panel.status.last_click} (before: path ${before.path}, node ${before.node})`);
      check("fillet picking: the view is drawn (not blank)", vP > 40 && vS > 40, `${vP}, ${vS} distinct colours`);
      await page.close();
    },
  },
];
