// The headless Chromium every browser script here opens: the machine's Debian chromium
// (or $CHROMIUM), SwiftShader WebGL2 (no GPU), a 1400×900 window at one device pixel per
// CSS pixel, and on every page a recorder of the gaps between animation frames
// (`window.__frameGaps`, ms), so a frame the app blocks shows as a long gap.
import { chromium } from "playwright-core";

export async function openBrowser() {
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    args: [
      "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
    ],
  });
  const context = await browser.newContext({ viewport: { width: 1400, height: 900 }, deviceScaleFactor: 1 });
  await recordFrameGaps(context);
  return { browser, context };
}

// Records the gaps between animation frames on every page of a context, or on one page
// (`window.__frameGaps`, ms; harness.mjs's resetFrames / recordFrames read them).
export async function recordFrameGaps(contextOrPage) {
  await contextOrPage.addInitScript(() => {
    window.__frameGaps = [];
    let last = null;
    const tick = (t) => {
      if (last !== null) window.__frameGaps.push(t - last);
      last = t;
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}
