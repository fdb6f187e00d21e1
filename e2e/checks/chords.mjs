// The chords tab: the parabola's equal-error chords against equal-interval and
// equal-step nodes, the plots, the tolerance slider.
import {
  check, clickRect, clickUntil, dragSlider, drawnVariety, openSettled, panelDone, recordFrames, resetFrames, shotPath, status,
  waitFor,
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
      // The tab is named by its subject; its help cites the article it follows.
      const h0 = await status(page);
      check("chords tab: named by its subject, its source cited", h0.panel.title === TAB && /Node calculation of equal-error/.test(h0.panel.paper ?? ""),
        `${h0.panel.title}: ${h0.panel.paper}`);
      // The help box opens above the tab strip: the tab's button moves down.
      await clickUntil(page, "the help box open", (s) => s.ui.help, (s) => s.ui[TAB][1] > h0.ui[TAB][1]);
      await page.screenshot({ path: shotPath("08b-chords-help.png") });
      // Help says what draws the frames: here WebGL2 on SwiftShader, so a software rasteriser.
      const h1 = await status(page);
      check("Help names the graphics API and that a software rasteriser draws here",
        /^• Drawn with WebGL2 by a software rasteriser/.test(h1.graphics ?? ""), h1.graphics);
      await page.close();
    },
  },
];
