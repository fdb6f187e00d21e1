// WebGPU where the browser has it. These flags give headless Chromium a SwiftShader WebGPU
// adapter that really renders (with --enable-unsafe-webgpu alone it draws nothing); the
// other checks run on WebGL2, wgpu's fallback. A browser of its own for each check. The
// page loads its WebGPU build here (web/index.html), and its WebGL2 build when that one
// cannot be fetched or cannot start.
import { chromium } from "playwright-core";
import { recordFrameGaps } from "../browser.mjs";
import { VIEW, check, dragSlider, drawnVariety, recordFrames, resetFrames, waitFor, settled } from "../harness.mjs";

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

// A page of the app in a browser of its own with a WebGPU adapter: `prepare(page)` runs before
// the app opens, then `checks(page, wasms)` with the page's wasm files as they are fetched; a
// throw (a state never reached) is the one failed check `failed`.
async function onWebGpuPage(url, failed, prepare, checks) {
  let browser = null;
  try {
    browser = await launchWithWebGpu();
    const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
    const wasms = recordPageWasms(page);
    await prepare(page);
    await page.goto(url);
    await checks(page, wasms);
  } catch (e) {
    check(failed, false, e.message);
  } finally {
    if (browser) await browser.close();
  }
}

// The WebGL2 build took over from the WebGPU one: it runs, on WebGL2, and draws (`shot`).
async function checkWebGlTookOver(page, wasms, name, shot) {
  const s = await waitFor(page, `the first path (${name})`, settled);
  const variety = await drawnVariety(page, shot, VIEW, 40);
  const build = await page.evaluate(() => window.interpolabBuild);
  check(`${name}: the WebGL2 build runs on a fresh canvas and draws`,
    build === "interpolab" && wasms.join() === "interpolab-webgpu_bg.wasm,interpolab_bg.wasm" && s.gpu_backend === "Gl"
      && s.periods > 100 && variety > 40,
    `build ${build}, page wasm fetched: ${wasms.join(", ")}, backend ${s.gpu_backend}, ${s.periods} periods, ${variety} colours`);
}

export const checks = [
  {
    name: "the app runs on WebGPU, from the page's WebGPU build",
    run: async ({ url }) => {
      const gpuErrors = [];
      await onWebGpuPage(url, "on WebGPU: the app runs", async (page) => {
        page.on("console", (m) => { if (m.type() === "error") gpuErrors.push(m.text()); });
        await recordFrameGaps(page);
      }, async (page, wasms) => {
        const sg = await waitFor(page, "the first path on WebGPU", settled);
        const varietyG = await drawnVariety(page, "10-webgpu.png", VIEW, 40);
        const build = await page.evaluate(() => window.interpolabBuild);
        check("on WebGPU: the app chose the WebGPU backend and drew its first frame",
          sg.gpu_backend === "BrowserWebGpu" && varietyG > 40, `backend ${sg.gpu_backend}, ${varietyG} distinct colours`);
        check("on WebGPU: Help says the app draws with WebGPU, by a software rasteriser here",
          /^• Drawn with WebGPU by a software rasteriser/.test(sg.graphics ?? ""), sg.graphics);
        check("on WebGPU: the page's WebGPU build runs, and no other page build was fetched",
          build === "interpolab-webgpu" && wasms.join() === "interpolab-webgpu_bg.wasm",
          `build ${build}, page wasm fetched: ${wasms.join(", ")}`);
        // The crease's feed slider, as crease.mjs drags it on WebGL2: the frames most
        // browsers meet (the WebGPU build), reported beside WebGL2's.
        await resetFrames(page);
        await dragSlider(page, sg.ui.feed_slider, 40, 70, 8);
        const s1 = await waitFor(page, "the path after moving the feed slider on WebGPU",
          (s) => s.feed_mm_per_min !== sg.feed_mm_per_min && settled(s));
        await recordFrames(page, "dragging the crease's feed slider on WebGPU", "crease on WebGPU");
        check("on WebGPU: moving the feed slider changes the number of periods", s1.periods !== sg.periods,
          `feed ${sg.feed_mm_per_min} → ${s1.feed_mm_per_min.toFixed(1)} mm/min, periods ${sg.periods} → ${s1.periods}`);
        check("on WebGPU: no console error", gpuErrors.length === 0, gpuErrors.slice(0, 3).join(" | "));
      });
    },
  },
  {
    name: "when the WebGPU build cannot be fetched, the WebGL2 build starts instead",
    run: ({ url }) => onWebGpuPage(url, "the WebGPU build blocked: the app runs",
      (page) => page.route(/interpolab-webgpu_bg\.wasm/, (r) => r.fulfill({ status: 404, body: "blocked by the e2e test" })),
      (page, wasms) => checkWebGlTookOver(page, wasms, "the WebGPU build blocked", "10b-webgpu-fallback.png")),
  },
  {
    name: "when the WebGPU build fetched cannot start, it hands over to the WebGL2 build",
    // The page's loader is given an adapter, the app's wgpu none: the WebGPU build is
    // fetched, fails to start and calls the loader's interpolabLoadWebGlPage.
    run: ({ url }) => onWebGpuPage(url, "the WebGPU build could not start: the app runs",
      (page) => page.addInitScript(() => {
        const gpu = navigator.gpu;
        const real = gpu.requestAdapter.bind(gpu);
        let asked = 0;
        gpu.requestAdapter = (o) => (asked++ === 0 ? real(o) : Promise.resolve(null));
      }),
      (page, wasms) => checkWebGlTookOver(page, wasms, "the WebGPU build could not start", "10c-webgpu-hand-over.png")),
  },
];
