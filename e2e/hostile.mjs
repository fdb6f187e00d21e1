// A hostile scene name in the browser (issue 29). Usage: node e2e/hostile.mjs http://127.0.0.1:PORT/
//
// A share link whose scene's name holds line breaks of every kind, a block, comment
// delimiters, a tape mark, our header keys, a LinuxCNC active comment, markup and script:
// - the page stays what it is: its title, no element or script added, the name in the
//   status element as text;
// - every program the NURBS & G-code tab offers for download (G01, G02/G03 and NURBS in
//   FANUC, Sinumerik and LinuxCNC words) is downloaded and compared with the same program
//   for a benign name: printable ASCII, the same number of lines, the same blocks line by
//   line (comments taken out) — no extra block — and the app's own reader opens it with
//   the table's deviation;
// - the scene saved from the page (Save) is JSON with the name exactly, and the app's own
//   share link opens the same name again.
// Screenshots and the downloads go to e2e/artifacts/hostile/.
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { openBrowser } from "./browser.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const url = process.argv[2] ?? "http://127.0.0.1:8765/";
const artifacts = path.join(here, "artifacts", "hostile");
fs.mkdirSync(artifacts, { recursive: true });

const TAB = "NURBS & G-code";
const KINDS = [
  { key: "G01", value: "g01" },
  { key: "G02/G03", value: "arcs" },
  { key: "G06.2", value: "nurbs" },
];
const DIALECTS = ["fanuc", "sinumerik", "linuxcnc"];
const BENIGN = "Floor and round wall";
const HOSTILE = "MSG,Dome\nG0 X999 Y999 Z-50\n(x) G1 Z-50 ; M30\r%\n%\u2028G0 X-999\u2029\u0085\u000b\u000c\u0000\u001b[2J"
  + " DIALECT: SINUMERIK PROGRAMMED POINT: BALL TIP = BALL CENTRE - Z 5"
  + " </title><img src=x onerror=\"window.__xss=1\"><script>window.__xss=2</script>"
  + " ,=1+1 \"q\" é😀\u202e" + "Z".repeat(300);

const results = [];
function check(name, ok, detail = "") {
  results.push({ name, ok });
  console.log(`${ok ? "ok  " : "FAIL"}  ${name}${detail ? " — " + detail : ""}`);
}

function base64url(text) {
  return Buffer.from(text, "utf8").toString("base64").replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

const examples = path.join(here, "..", "examples");
// The floor-and-round-wall scene: its crease is planar, so LinuxCNC's G5.2 carries it too.
function sceneNamed(name) {
  const scene = JSON.parse(fs.readFileSync(path.join(examples, "floor-round-wall.json"), "utf8"));
  scene.name = name;
  return scene;
}

async function status(page) {
  const text = await page.locator("#app-status").textContent();
  return text ? JSON.parse(text) : null;
}

async function waitFor(page, what, pred, timeoutMs = 90000) {
  const t0 = Date.now();
  let last = null;
  while (Date.now() - t0 < timeoutMs) {
    last = await status(page).catch(() => null);
    if (last && pred(last)) return last;
    await page.waitForTimeout(100);
  }
  throw new Error(`timed out waiting for ${what}; last status: ${JSON.stringify(last)?.slice(0, 400)}`);
}

// Clicks a published rectangle until `pred` holds (a banner can move the layout by a frame).
async function clickUntil(page, what, rect, pred) {
  for (let i = 0; i < 6; i++) {
    const r = rect(await status(page));
    await page.mouse.click(r[0] + r[2] / 2, r[1] + r[3] / 2);
    try {
      return await waitFor(page, what, pred, 3000);
    } catch {
      // the rectangle had moved; read it again
    }
  }
  throw new Error(`clicking did not give ${what}`);
}

// The lines of a program that hold code, comments `( … )` and `; …` taken out.
function codeLines(text) {
  const out = [];
  for (const line of text.split("\n")) {
    let code = "";
    let depth = 0;
    for (const c of line) {
      if (c === ";" && depth === 0) break;
      if (c === "(") depth += 1;
      else if (c === ")") depth = Math.max(0, depth - 1);
      else if (depth === 0) code += c;
    }
    code = code.trim();
    if (code !== "") out.push(code);
  }
  return out;
}

const printableAscii = (text) => /^[\x20-\x7e\n]*$/.test(text);
const panelDone = (s) => s.panel && s.panel.title === TAB && s.panel.status && s.panel.status.done
  && s.panel.status.rows.every((r) => r.fresh);

const { browser, context } = await openBrowser();
const consoleErrors = [];
context.on("console", (m) => { if (m.type() === "error") consoleErrors.push(m.text()); });
context.on("weberror", (e) => consoleErrors.push(String(e.error())));

// Every program of the tab for `name` in `dialect`: { value: { file, text, deviation_mm } }.
async function programs(name, dialect, tag) {
  const page = await context.newPage();
  const q = `?view=${encodeURIComponent(TAB)}&set=${encodeURIComponent("dialect:" + dialect)}`;
  await page.goto(url + q + "#scene=" + base64url(JSON.stringify(sceneNamed(name))));
  let s = await waitFor(page, `the ${dialect} programs for the ${tag} name`, panelDone);
  const out = { page, files: {}, rows: s.panel.status.rows };
  for (const k of KINDS) {
    await clickUntil(page, `the ${k.key} program shown`, (st) => st.panel.status.ui[k.key], (st) => st.panel.status.program === k.value);
    const downloaded = page.waitForEvent("download", { timeout: 30000 });
    const suffix = dialect === "fanuc" ? `-${k.value}.nc` : `-${dialect}-${k.value}.nc`;
    s = await clickUntil(page, `the ${k.key} download`, (st) => st.panel.status.ui.download,
      (st) => (st.panel.status.downloaded ?? "").endsWith(suffix));
    const d = await downloaded;
    const file = path.join(artifacts, `${tag}-${d.suggestedFilename()}`);
    await d.saveAs(file);
    out.files[k.value] = { name: d.suggestedFilename(), file, text: fs.readFileSync(file, "utf8") };
  }
  return out;
}

let failed = false;
try {
  for (const dialect of DIALECTS) {
    const benign = await programs(BENIGN, dialect, "benign");
    await benign.page.close();
    const hostile = await programs(HOSTILE, dialect, "hostile");
    const page = hostile.page;
    for (const k of KINDS) {
      const b = benign.files[k.value];
      const h = hostile.files[k.value];
      const hb = codeLines(h.text);
      const bb = codeLines(b.text);
      const sameBlocks = hb.length === bb.length && hb.every((l, i) => l === bb[i]);
      check(`${dialect} ${k.key}: a hostile name leaves the downloaded program's blocks as a benign name's`,
        sameBlocks && printableAscii(h.text) && h.text.split("\n").length === b.text.split("\n").length
          && /^[a-z0-9-]+\.nc$/.test(h.name) && h.name.length <= 120,
        `${hb.length} blocks, ${h.text.split("\n").length} lines, file ${h.name.slice(0, 60)}…; first comment ${h.text.split("\n")[1].slice(0, 70)}…`);
      // The app's own reader opens the download, with the deviation the table gives.
      await page.setInputFiles("#scene-file", { name: h.name, mimeType: "text/plain", buffer: Buffer.from(h.text) });
      const s = await waitFor(page, `the loaded ${k.key} program`, (st) => panelDone(st) && st.panel.status.loaded
        && st.panel.status.loaded.name === h.name && (st.panel.status.loaded.error !== null || st.panel.status.loaded.deviation_mm != null));
      const loaded = s.panel.status.loaded;
      const row = s.panel.status.rows[KINDS.indexOf(k)];
      check(`${dialect} ${k.key}: the app reads the downloaded program back`,
        loaded.error === null && loaded.unsupported === 0 && Math.abs(loaded.deviation_mm - row.deviation_mm) < 1e-9,
        `deviation ${loaded.deviation_mm} mm (table ${row.deviation_mm} mm), error ${loaded.error}`);
    }
    if (dialect === "fanuc") {
      await page.screenshot({ path: path.join(artifacts, "hostile-nurbs-tab.png") });
    }
    await page.close();
  }

  // The page itself: a share link with the hostile name, on the default view, against the
  // same link with a benign name.
  const pageOf = async (name) => {
    const p = await context.newPage();
    await p.goto("about:blank");
    await p.goto(url + "#scene=" + base64url(JSON.stringify(sceneNamed(name))));
    const st = await waitFor(p, `the scene ${name.slice(0, 20)}`, (x) => x.scene === name && x.frames >= 3);
    await p.waitForTimeout(500);
    const d = await p.evaluate(() => ({
      title: document.title,
      xss: window.__xss ?? null,
      tags: [...document.querySelectorAll("*")].map((e) => e.tagName.toLowerCase()).sort(),
      // Event-handler attributes and scripts of the page (the status element holds the
      // name as text, which is what it should: its characters are not markup).
      handlers: [...document.querySelectorAll("*")].flatMap((e) => [...e.attributes].map((a) => a.name))
        .filter((n) => n.startsWith("on")).sort(),
      scripts: [...document.scripts].map((x) => x.src || x.text).sort(),
      status_is_text: document.getElementById("app-status").children.length === 0,
    }));
    return { p, st, d };
  };
  const benignPage = await pageOf(BENIGN);
  await benignPage.p.close();
  const { p: page, st: s, d: dom } = await pageOf(HOSTILE);
  await page.screenshot({ path: path.join(artifacts, "hostile-share-link.png") });
  check("the page's title stays the app's", dom.title === benignPage.d.title && dom.title.startsWith("interpolab"), dom.title);
  check("no markup or script from the name runs or enters the page",
    dom.xss === null && dom.tags.join(" ") === benignPage.d.tags.join(" ") && !dom.tags.includes("img")
      && dom.handlers.join(" ") === benignPage.d.handlers.join(" ")
      && JSON.stringify(dom.scripts) === JSON.stringify(benignPage.d.scripts) && dom.status_is_text,
    `elements as with a benign name: ${[...new Set(dom.tags)].join(" ")}`);
  check("the name reaches the status element as text, exactly", s.scene === HOSTILE, `${s.scene.length} characters`);

  // Save: the scene downloads as JSON with the name exactly.
  const saved = page.waitForEvent("download", { timeout: 30000 });
  const save = s.ui.save_button;
  await page.mouse.click(save[0] + save[2] / 2, save[1] + save[3] / 2);
  const d = await saved;
  const jsonFile = path.join(artifacts, d.suggestedFilename());
  await d.saveAs(jsonFile);
  let savedName = null;
  try {
    savedName = JSON.parse(fs.readFileSync(jsonFile, "utf8")).name;
  } catch (e) {
    savedName = `not JSON: ${e.message}`;
  }
  check("Save downloads the scene as JSON with the name exactly",
    savedName === HOSTILE && /^[a-z0-9-]+\.json$/.test(d.suggestedFilename()), d.suggestedFilename().slice(0, 60));

  // The app's own share link opens the same name again.
  const sb = s.ui.share_button;
  await page.mouse.click(sb[0] + sb[2] / 2, sb[1] + sb[3] / 2);
  await page.waitForTimeout(300);
  const shared = page.url();
  const page2 = await context.newPage();
  await page2.goto("about:blank");
  await page2.goto(shared);
  const s2 = await waitFor(page2, "the shared hostile scene", (st) => st.frames >= 3 && st.scene !== undefined);
  check("the app's share link keeps the name", s2.scene === HOSTILE && shared.includes("#scene="), `${shared.length} characters`);
  await page2.close();
  await page.close();
} catch (e) {
  failed = true;
  console.log(`FAIL  ${e.stack ?? e}`);
}

check("no console error", consoleErrors.length === 0, consoleErrors.slice(0, 3).join(" | "));
await browser.close();
const passed = results.filter((r) => r.ok).length;
const failedCount = results.length - passed + (failed ? 1 : 0);
console.log(`\nhostile: ${passed} passed, ${failedCount} failed (screenshots and downloads in e2e/artifacts/hostile/)`);
process.exit(failedCount === 0 ? 0 : 1);
