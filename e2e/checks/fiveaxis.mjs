// The 5-axis tab: Example 1 before and after its steps are inserted, the iteration
// table following the tolerance slider, the tip-bound switch.
import {
  check, clickRect, drawnVariety, openSettled, panelDone, recordFrames, resetFrames, shotPath, waitFor,
} from "../harness.mjs";

const TAB = "5-axis steps";
const done = panelDone(TAB);

export const checks = [
  {
    name: "Example 1's single block gouges, drawn in the 3D view",
    run: async ({ context, url, state }) => {
      const { page, s } = await openSettled(context, url, "the app for the panel tabs");
      await resetFrames(page);
      await clickRect(page, s.ui[TAB]);
      const f1 = await waitFor(page, "the 5-axis view (Example 1, one block)", done);
      await recordFrames(page, "opening the 5-axis tab", "5-axis");
      const p1 = f1.panel.status;
      check("5-axis tab: Example 1's single block gouges by 8.79 mm", p1.blocks === 2 && Math.abs(p1.worst_delta_mm - 8.79) < 0.01,
        `${p1.blocks} blocks, δ = ${p1.worst_delta_mm.toFixed(4)} mm`);
      const v1 = await drawnVariety(page, "06-fiveaxis-example1-before.png", p1.ui.view, 40);
      check("5-axis tab: the 3D view is drawn (not blank)", v1 > 40, `${v1} distinct colours in the view`);
      Object.assign(state, { page, p1 });
    },
  },
  {
    name: "after the steps every segment is within E",
    run: async ({ state }) => {
      const { page, p1 } = state;
      await clickRect(page, p1.ui.after);
      const f2 = await waitFor(page, "Example 1 after the steps", (s) => done(s) && !s.panel.status.before);
      await page.screenshot({ path: shotPath("07-fiveaxis-example1-after.png") });
      const p2 = f2.panel.status;
      check("5-axis tab: after the steps every segment is within E", p2.blocks === 32 && p2.worst_delta_mm <= p2.tol_mm && p2.error === "",
        `${p2.blocks} blocks, worst δ ${(p2.worst_delta_mm * 1e3).toFixed(4)} µm, E ${p2.tol_mm} mm, iterations ${JSON.stringify(p2.compare)}`);
      const t = p2.time;
      check("5-axis tab: the time of the before and after plans on the machine's preset",
        t && t.machine === "table-ac" && t.feed_default === true && t.error === ""
          && Number.isFinite(t.before_s) && Number.isFinite(t.after_s) && t.before_s > 0 && t.after_s > 0,
        t ? `${t.machine} at F ${t.feed_mm_per_min} mm/min: before ${t.before_s} s, after ${t.after_s} s` : "no time in the status");
      state.p2 = p2;
    },
  },
  {
    name: "the iteration table follows the tolerance slider",
    run: async ({ state }) => {
      const { page, p2 } = state;
      const [tx, ty, , th] = p2.ui.tolerance;
      await resetFrames(page);
      await page.mouse.move(tx + 40, ty + th / 2);
      await page.mouse.down();
      await page.mouse.move(tx + 15, ty + th / 2, { steps: 6 });
      await page.mouse.up();
      const f3 = await waitFor(page, "the plan at a new tolerance", (s) => done(s) && s.panel.status.tol_mm !== p2.tol_mm);
      await recordFrames(page, "dragging the 5-axis tolerance slider", "5-axis");
      const p3 = f3.panel.status;
      check("5-axis tab: the iteration table follows the tolerance slider",
        p3.blocks > p2.blocks && p3.compare.secant !== p2.compare.secant && Object.values(p3.compare).every((v) => Number.isInteger(v)),
        `E ${p2.tol_mm} → ${p3.tol_mm.toFixed(5)} mm: ${p3.blocks} blocks, ${JSON.stringify(p3.compare)}`);
      state.p3 = p3;
    },
  },
  {
    name: "the tip-bound switch replans within E",
    run: async ({ state }) => {
      const { page, p3 } = state;
      await clickRect(page, p3.ui.bound_tip);
      const f3b = await waitFor(page, "the plan with the tip bound", (s) => done(s) && s.panel.status.bound_tip);
      await page.screenshot({ path: shotPath("07b-fiveaxis-tip-bound.png") });
      const p3b = f3b.panel.status;
      check("5-axis tab: the tip-bound switch replans within E",
        p3b.blocks >= p3.blocks && p3b.worst_delta_mm <= p3b.tol_mm && p3b.error === "", `${p3.blocks} → ${p3b.blocks} blocks`);
      await page.close();
    },
  },
];
