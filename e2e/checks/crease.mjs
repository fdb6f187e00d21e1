// The crease tab (the page as it opens): the first frame, the feed slider, a run toward
// path.end.
import {
  VIEW, base64url, check, clickRect, drawnVariety, openSettled, readText, recordFrames, resetFrames, shotPath,
  waitFor, settled,
} from "../harness.mjs";

export const checks = [
  {
    name: "the page loads, computes the preset and draws its first frame",
    run: async ({ context, url, state }) => {
      // Which of the page's two builds this browser (WebGL2, no WebGPU adapter) fetches.
      const wasms = [];
      const onRequest = (r) => { if (/_bg\.wasm(\?|$)/.test(r.url())) wasms.push(new URL(r.url()).pathname.slice(1)); };
      context.on("request", onRequest);
      const t0 = Date.now();
      const { page, s } = await openSettled(context, url, "the first computed path");
      const loadMs = Date.now() - t0;
      context.off("request", onRequest);
      const build = await page.evaluate(() => window.interpolabBuild);
      const pageWasms = wasms.filter((w) => !w.startsWith("interpolab-worker"));
      check("without a WebGPU adapter the page loads its build with WebGL2, and only that one",
        build === "interpolab" && pageWasms.length === 1 && pageWasms[0] === "interpolab_bg.wasm" && s.gpu_backend === "Gl",
        `build ${build}, page wasm fetched: ${pageWasms.join(", ")}, backend ${s.gpu_backend}`);
      const variety = await drawnVariety(page, "01-first-frame.png", VIEW, 40);
      check("page loads and computes the preset", s.periods > 100, `${s.periods} periods, ${s.scene}`);
      check("first frame is drawn (3D view not blank)", variety > 40, `${variety} distinct colours in the view`);
      check("time to first frame recorded", typeof s.first_frame_ms === "number",
        `first frame at ${Math.round(s.first_frame_ms)} ms after navigation; settled after ${loadMs} ms`);
      Object.assign(state, { page, s0: s });
    },
  },
  {
    name: "the feed slider changes the number of periods",
    run: async ({ state }) => {
      const { page, s0 } = state;
      // The slider's rail is its first 100 points; press on it and drag a little to the right.
      const [x, y, , h] = s0.ui.feed_slider;
      const handleY = y + h / 2;
      await resetFrames(page);
      await page.mouse.move(x + 40, handleY);
      await page.mouse.down();
      await page.mouse.move(x + 70, handleY, { steps: 8 });
      await page.mouse.up();
      const s1 = await waitFor(page, "the path after moving the feed slider", (s) => s.feed_mm_per_min !== s0.feed_mm_per_min && settled(s));
      await recordFrames(page, "dragging the crease's feed slider", "crease");
      await page.screenshot({ path: shotPath("02-after-feed-slider.png") });
      check("moving the feed slider changes the number of periods", s1.periods !== s0.periods,
        `feed ${s0.feed_mm_per_min} → ${s1.feed_mm_per_min.toFixed(1)} mm/min, periods ${s0.periods} → ${s1.periods}`);
      await page.close();
    },
  },
  {
    name: "a run away from path.end names the path.direction to set, and its button runs toward it",
    run: async ({ context, url }) => {
      const groove = JSON.parse(readText("tests", "data", "groove-end-behind-start.json"));
      const page = await context.newPage();
      await page.goto(url + "#scene=" + base64url(JSON.stringify(groove)));
      const sG = await waitFor(page, "the groove scene", (s) => s.scene === groove.name && settled(s));
      await page.screenshot({ path: shotPath("05a-end-not-reached.png") });
      check("a run away from path.end names the path.direction to set",
        sG.stop === "left_domain" && (sG.end_note || "").includes("path.direction to [1.000, 0.000, 0.000]"), sG.end_note);
      await clickRect(page, sG.ui.run_toward_end);
      const sG2 = await waitFor(page, "the run toward path.end", (s) => s.stop === "reached_end" && settled(s));
      await page.screenshot({ path: shotPath("05b-end-reached.png") });
      check("its button runs toward path.end", sG2.end_note === null && sG2.periods === 800, `${sG2.periods} periods`);
      await page.close();
    },
  },
];
