// WebGPU where the browser has it. These flags give headless Chromium a SwiftShader WebGPU
// adapter that really renders (with --enable-unsafe-webgpu alone it draws nothing); the
// other checks run on WebGL2, wgpu's fallback. A browser of its own for each check. The
// page loads its WebGPU build here (web/index.html), and its WebGL2 build when that one
// cannot be fetched or cannot start.
import { chromium } from "playwright-core";
import { recordFrameGaps } from "../browser.mjs";
import { VIEW, check, drawnVariety, recordFrames, resetFrames, waitFor, settled } from "../harness.mjs";

const launchWithWebGpu = () => chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  args: [
    "--no-sandbox", "--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-vulkan=swiftshader",
    "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync",
  ],
});

// The page's wasm files a page fetched (the worker's left out).
function recordPageWasms(page) {
  const wasms = [];
  page.on("request", (r) => {
    const name = new URL(r.url()).pathname.slice(1);
    if (/_bg\.wasm$/.test(name) && !name.startsWith("interpolab-worker")) wasms.push(name);
  });
  return wasms;
}

export const checks = [
  {
    name: "the app runs on WebGPU, from the page's WebGPU build",
    run: async ({ url }) => {
      let gpuBrowser = null;
      try {
        gpuBrowser = await launchWithWebGpu();
        const gpuPage = await gpuBrowser.newPage({ viewport: { width: 1400, height: 900 } });
        const gpuErrors = [];
        gpuPage.on("console", (m) => { if (m.type() === "error") gpuErrors.push(m.text()); });
        const wasms = recordPageWasms(gpuPage);
        await recordFrameGaps(gpuPage);
        await gpuPage.goto(url);
        const sg = await waitFor(gpuPage, "the first path on WebGPU", settled);
        const varietyG = await drawnVariety(gpuPage, "10-webgpu.png", VIEW, 40);
        const build = await gpuPage.evaluate(() => window.interpolabBuild);
        check("on WebGPU: the app chose the WebGPU backend and drew its first frame",
          sg.gpu_backend === "BrowserWebGpu" && varietyG > 40, `backend ${sg.gpu_backend}, ${varietyG} distinct colours`);
        check("on WebGPU: Help says the app draws with WebGPU, by a software rasteriser here",
          /^• Drawn with WebGPU by a software rasteriser/.test(sg.graphics ?? ""), sg.graphics);
        check("on WebGPU: the page's WebGPU build runs, and no other page build was fetched",
          build === "interpolab-webgpu" && wasms.length === 1 && wasms[0] === "interpolab-webgpu_bg.wasm",
          `build ${build}, page wasm fetched: ${wasms.join(", ")}`);
        // The crease's feed slider, as crease.mjs drags it on WebGL2: the frames most
        // browsers meet (the WebGPU build), reported beside WebGL2's.
        const [x, y, , h] = sg.ui.feed_slider;
        await resetFrames(gpuPage);
        await gpuPage.mouse.move(x + 40, y + h / 2);
        await gpuPage.mouse.down();
        await gpuPage.mouse.move(x + 70, y + h / 2, { steps: 8 });
        await gpuPage.mouse.up();
        const s1 = await waitFor(gpuPage, "the path after moving the feed slider on WebGPU",
          (s) => s.feed_mm_per_min !== sg.feed_mm_per_min && settled(s));
        await recordFrames(gpuPage, "dragging the crease's feed slider on WebGPU", "crease on WebGPU");
        check("on WebGPU: moving the feed slider changes the number of periods", s1.periods !== sg.periods,
          `feed ${sg.feed_mm_per_min} → ${s1.feed_mm_per_min.toFixed(1)} mm/min, periods ${sg.periods} → ${s1.periods}`);
        check("on WebGPU: no console error", gpuErrors.length === 0, gpuErrors.slice(0, 3).join(" | "));
      } catch (e) {
        check("on WebGPU: the app runs", false, e.message);
      } finally {
        if (gpuBrowser) await gpuBrowser.close();
      }
    },
  },
  {
    name: "when the WebGPU build cannot be fetched, the build with WebGL2 starts instead",
    run: async ({ url }) => {
      let gpuBrowser = null;
      try {
        gpuBrowser = await launchWithWebGpu();
        const page = await gpuBrowser.newPage({ viewport: { width: 1400, height: 900 } });
        await page.route(/interpolab-webgpu_bg\.wasm/, (r) => r.fulfill({ status: 404, body: "blocked by the e2e test" }));
        const wasms = recordPageWasms(page);
        await page.goto(url);
        const s = await waitFor(page, "the first path after the fallback", settled);
        const variety = await drawnVariety(page, "10b-webgpu-fallback.png", VIEW, 40);
        const build = await page.evaluate(() => window.interpolabBuild);
        check("the WebGPU build blocked: the build with WebGL2 runs and draws",
          build === "interpolab" && wasms.includes("interpolab_bg.wasm") && s.periods > 100 && variety > 40,
          `build ${build}, page wasm fetched: ${wasms.join(", ")}, backend ${s.gpu_backend}, ${s.periods} periods, ${variety} colours`);
      } catch (e) {
        check("the WebGPU build blocked: the app runs", false, e.message);
      } finally {
        if (gpuBrowser) await gpuBrowser.close();
      }
    },
  },
  {
    name: "when the WebGPU build fetched cannot start, it hands over to the WebGL2 build",
    run: async ({ url }) => {
      let gpuBrowser = null;
      try {
        gpuBrowser = await launchWithWebGpu();
        const page = await gpuBrowser.newPage({ viewport: { width: 1400, height: 900 } });
        // The page's loader is given an adapter, the app's wgpu none: the WebGPU build is
        // fetched, fails to start and calls the loader's interpolabLoadWebGlPage.
        await page.addInitScript(() => {
          const gpu = navigator.gpu;
          const real = gpu.requestAdapter.bind(gpu);
          let asked = 0;
          gpu.requestAdapter = (o) => (asked++ === 0 ? real(o) : Promise.resolve(null));
        });
        const wasms = recordPageWasms(page);
        await page.goto(url);
        const s = await waitFor(page, "the first path after the hand-over", settled);
        const variety = await drawnVariety(page, "10c-webgpu-hand-over.png", VIEW, 40);
        const build = await page.evaluate(() => window.interpolabBuild);
        check("the WebGPU build could not start: the WebGL2 build runs on a fresh canvas and draws",
          build === "interpolab" && wasms.join() === "interpolab-webgpu_bg.wasm,interpolab_bg.wasm" && s.gpu_backend === "Gl" && variety > 40,
          `build ${build}, page wasm fetched: ${wasms.join(", ")}, backend ${s.gpu_backend}, ${variety} colours`);
      } catch (e) {
        check("the WebGPU build could not start: the app runs", false, e.message);
      } finally {
        if (gpuBrowser) await gpuBrowser.close();
      }
    },
  },
];
