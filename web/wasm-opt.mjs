// Trunk post-build hook (Trunk.toml): shrinks the release wasm with wasm-opt from npm's
// `binaryen` (a JS/wasm build, pinned in web/package.json and installed by
// `scripts/setup.sh build`; Debian's binaryen 108 breaks the module and Trunk's own download
// of a prebuilt wasm-opt is not allowed here), then updates the wasm's `integrity` hash in
// the staged index.html, which Trunk wrote before this hook runs.
//
// Dev builds (`trunk build` / `trunk serve` without --release) are left as they are, and so
// is any build with INTERPOLAB_WASM_OPT=0 (wasm-opt adds 1.5–3 minutes).
import { spawnSync } from "node:child_process";
import { createHash } from "node:crypto";
import { existsSync, readdirSync, readFileSync, statSync, writeFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const staging = process.env.TRUNK_STAGING_DIR;
if (process.env.TRUNK_PROFILE !== "release") process.exit(0);
// A quicker release build for local iterations: INTERPOLAB_WASM_OPT=0 trunk build --release.
if (process.env.INTERPOLAB_WASM_OPT === "0") {
  console.log("web/wasm-opt.mjs: skipped (INTERPOLAB_WASM_OPT=0); the wasm is not shrunk");
  process.exit(0);
}
if (!staging) {
  console.error("web/wasm-opt.mjs: TRUNK_STAGING_DIR is not set (run it as Trunk's post_build hook)");
  process.exit(1);
}
const wasmOpt = join(here, "node_modules", ".bin", "wasm-opt");
if (!existsSync(wasmOpt)) {
  console.error(
    "web/wasm-opt.mjs: wasm-opt is not installed, so the download stays unoptimised " +
      "(about 25% larger); run scripts/setup.sh build (npm binaryen in web/) to install it",
  );
  process.exit(0);
}

const wasms = readdirSync(staging).filter((f) => f.endsWith("_bg.wasm"));
if (wasms.length === 0) console.error(`web/wasm-opt.mjs: no *_bg.wasm in ${staging}; nothing to shrink`);
for (const name of wasms) {
  const path = join(staging, name);
  const before = statSync(path).size;
  const t0 = Date.now();
  // -Oz: the smallest code; the wasm's own target_features section tells wasm-opt which
  // features (bulk memory, reference types, …) it may keep using. Names and producers are
  // dropped (no -g). The Web Worker's module computes (the simulation, the table rows) and
  // is built for speed (Cargo profile worker-release, opt-level 3): -O3 keeps it so.
  const level = name.startsWith("interpolab-worker") ? "-O3" : "-Oz";
  const run = spawnSync(wasmOpt, [level, "--strip-debug", "--strip-producers", path, "-o", path], {
    stdio: "inherit",
  });
  if (run.status !== 0) {
    console.error(`web/wasm-opt.mjs: wasm-opt failed on ${name} (status ${run.status})`);
    process.exit(1);
  }
  const bytes = readFileSync(path);
  const integrity = "sha384-" + createHash("sha384").update(bytes).digest("base64");
  const html = join(staging, "index.html");
  const text = readFileSync(html, "utf8");
  // The preload link of this wasm carries Trunk's hash of the unoptimised file.
  const link = new RegExp(`(href="[^"]*${name.replace(/[.]/g, "\\.")}"[^>]*integrity=")sha384-[^"]*(")`);
  // The Web Worker's module (interpolab-worker_bg.wasm) is fetched by its own loader script,
  // not through index.html: nothing to update.
  if (name.startsWith("interpolab-worker")) {
    console.log(`web/wasm-opt.mjs: ${name} ${before} -> ${bytes.length} bytes in ${((Date.now() - t0) / 1000).toFixed(1)} s (worker)`);
    continue;
  }
  if (!link.test(text)) {
    console.error(`web/wasm-opt.mjs: no integrity attribute for ${name} in index.html`);
    process.exit(1);
  }
  writeFileSync(html, text.replace(link, `$1${integrity}$2`));
  console.log(
    `web/wasm-opt.mjs: ${name} ${before} -> ${bytes.length} bytes in ${((Date.now() - t0) / 1000).toFixed(1)} s`,
  );
}
