// The chords tab: the parabola's equal-error chords against equal-interval and
// equal-step nodes, the plots, the tolerance slider.
import {
  check, clickRect, dragSlider, drawnVariety, openSettled, panelDone, recordFrames, resetFrames, waitFor,
} from "../harness.mjs";

const TAB = "Chords";
const done = panelDone(TAB);

export const checks = [
  {
    name: "the parabola's equal-error chords are the fewest, the plots drawn, the tolerance slider followed",
    run: async ({ context, url }) => {
      const { page, s } = await openSettled(context, url, "the app for the chords tab");
      await resetFrames(page);
      await clickRect(page, s.ui[TAB]);
      const f4 = await waitFor(page, "the chords view", done);
      await recordFrames(page, "opening the chords tab", "chords");
      const rows = f4.panel.status.rows;
      check("chords tab: the parabola's equal-error chords are the fewest",
        rows["equal-error"].nodes === 18 && rows["equal-interval, sized by ρ_min"].nodes === 23 && rows["equal-step, sized by ρ_min"].nodes === 41,
        `${rows["equal-error"].nodes} / ${rows["equal-interval, sized by ρ_min"].nodes} / ${rows["equal-step, sized by ρ_min"].nodes} nodes at d = ${f4.panel.status.tol_mm} mm`);
      const v2 = await drawnVariety(page, "08-chords-parabola.png", f4.panel.status.ui.plots, 12);
      check("chords tab: the plots are drawn (not blank)", v2 > 12, `${v2} distinct colours in the plots`);
      await resetFrames(page);
      await dragSlider(page, f4.panel.status.ui.tolerance);
      await waitFor(page, "the chords at a new tolerance", (s) => done(s) && s.panel.status.tol_mm !== f4.panel.status.tol_mm);
      await recordFrames(page, "dragging the chords tolerance slider", "chords");
      await page.close();
    },
  },
];
