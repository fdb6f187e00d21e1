// Scenes in and out of the page: open a file (a bad one refused, the scene kept), the share
// link, a link made outside the app, a broken link, and the last scene kept across reloads.
import {
  base64url, check, clickRect, example, openSettled, readText, shotPath, waitFor, waitUntil, settled,
} from "../harness.mjs";

// eframe's storage key of the app's scene (src/app/mod.rs, STORAGE_SCENE): local storage.
const STORAGE_SCENE = "interpolab.scene";

export const checks = [
  {
    name: "a bad scene file is refused and the scene kept",
    run: async ({ context, url, state }) => {
      const { page, s: s1 } = await openSettled(context, url);
      const bad = example("torus-plane.json");
      bad.tool.radius = -2;
      await page.setInputFiles("#scene-file", { name: "bad-scene.json", mimeType: "application/json", buffer: Buffer.from(JSON.stringify(bad)) });
      const s2 = await waitFor(page, "the error about the bad file", (s) => s.error.includes("bad-scene.json"));
      await page.screenshot({ path: shotPath("03-bad-file.png") });
      check("a bad scene file shows what is wrong", s2.error.includes("tool.radius") && s2.error.includes("kept"), s2.error);
      check("… and keeps the current scene", s2.scene === s1.scene && s2.periods === s1.periods);
      state.page = page;
    },
  },
  {
    name: "a scene file opens",
    run: async ({ state }) => {
      const { page } = state;
      await page.setInputFiles("#scene-file", { name: "torus.json", mimeType: "application/json", buffer: Buffer.from(readText("examples", "torus-plane.json")) });
      const s3 = await waitFor(page, "the opened file", (s) => s.scene.startsWith("Torus") && settled(s));
      check("a scene file opens", s3.periods > 100, `${s3.scene}: ${s3.periods} periods`);
      state.s3 = s3;
    },
  },
  {
    name: "the share link puts the scene in the address and restores it in a fresh page",
    run: async ({ context, state }) => {
      const { page, s3 } = state;
      await clickRect(page, s3.ui.share_button);
      // The address changes when the app has handled the click (a state, not a time).
      const shared = await waitUntil(page, "the share link in the address", async () => (page.url().includes("#scene=") ? page.url() : null), 60000)
        .catch(() => page.url());
      check("Share link puts the scene in the URL", shared.includes("#scene="), `${shared.length} characters`);
      const page2 = await context.newPage();
      await page2.goto("about:blank");
      await page2.goto(shared);
      const s4 = await waitFor(page2, "the shared scene", settled);
      await page2.screenshot({ path: shotPath("04-share-link.png") });
      check("a share link restores the scene", s4.scene === s3.scene && s4.periods === s3.periods, `${s4.scene}, ${s4.periods} periods`);
      await page2.close();
      await page.close();
    },
  },
  {
    name: "a link made outside the app opens its scene",
    run: async ({ context, url, state }) => {
      const dome = example("sphere-plane.json");
      const page3 = await context.newPage();
      await page3.goto(url + "#scene=" + base64url(JSON.stringify(dome)));
      const s5 = await waitFor(page3, "the linked dome scene", (s) => s.scene === dome.name && settled(s));
      check("a hand-made link opens its scene", s5.periods > 100, `${s5.periods} periods`);
      Object.assign(state, { page3, dome });
    },
  },
  {
    name: "a broken link says what is wrong",
    run: async ({ context, url }) => {
      const page4 = await context.newPage();
      await page4.goto(url + "#scene=" + base64url('{"format":"interpolab-scene/1"}'));
      const s6 = await waitFor(page4, "the broken-link error", (s) => s.error !== "" && s.frames >= 3);
      await page4.screenshot({ path: shotPath("05-broken-link.png") });
      check("a broken link says what is wrong", s6.error.includes("link") && s6.error.includes("missing"), s6.error);
      await page4.close();
    },
  },
  {
    name: "the last scene is kept across reloads",
    run: async ({ context, url, state }) => {
      // eframe keeps the scene in local storage (auto-saved every 5 s). Only page3 stays
      // open, so no other page overwrites the stored scene meanwhile; the reload waits until
      // the store holds page3's scene, however long the save takes on a loaded machine.
      const { page3, dome } = state;
      for (const p of context.pages()) if (p !== page3) await p.close();
      await waitUntil(page3, "the scene saved in local storage", () => page3.evaluate(
        ([key, name]) => { try { return JSON.parse(localStorage.getItem(key) ?? "null")?.name === name; } catch { return false; } },
        [STORAGE_SCENE, dome.name]));
      await page3.goto(url);
      const s7 = await waitFor(page3, "the reloaded scene", settled);
      check("the last scene is kept across reloads", s7.scene === dome.name, s7.scene);
      await page3.close();
    },
  },
];
