// WebGPU where the browser has it. These flags give headless Chromium a SwiftShader WebGPU
// adapter that really renders (with --enable-unsafe-webgpu alone it draws nothing); the
// other checks run on WebGL2, wgpu's fallback. A browser of its own.
import { chromium } from "playwright-core";
import { VIEW, check, drawnVariety, waitFor, settled } from "../harness.mjs";

export const checks = [
  {
    name: "the app runs on WebGPU",
    run: async ({ url }) => {
      let gpuBrowser = null;
      try {
        gpuBrowser = await chromium.launch({
          executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
          headless: true,
          args: [
            "--no-sandbox", "--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-vulkan=swiftshader",
            "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
            "--disable-component-update", "--disable-sync",
          ],
        });
        const gpuPage = await gpuBrowser.newPage({ viewport: { width: 1400, height: 900 } });
        const gpuErrors = [];
        gpuPage.on("console", (m) => { if (m.type() === "error") gpuErrors.push(m.text()); });
        await gpuPage.goto(url);
        const sg = await waitFor(gpuPage, "the first path on WebGPU", settled);
        const varietyG = await drawnVariety(gpuPage, "10-webgpu.png", VIEW, 40);
        check("on WebGPU: the app chose the WebGPU backend and drew its first frame",
          sg.gpu_backend === "BrowserWebGpu" && varietyG > 40, `backend ${sg.gpu_backend}, ${varietyG} distinct colours`);
        check("on WebGPU: no console error", gpuErrors.length === 0, gpuErrors.slice(0, 3).join(" | "));
      } catch (e) {
        check("on WebGPU: the app runs", false, e.message);
      } finally {
        if (gpuBrowser) await gpuBrowser.close();
      }
    },
  },
];
