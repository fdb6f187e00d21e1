// Trunk post-build hook (Trunk.toml). Two steps on the staged files:
//
// 1. Release builds: shrinks each wasm with wasm-opt from npm's `binaryen` (a JS/wasm build,
//    pinned in web/package.json and installed by `scripts/setup.sh build`; Debian's binaryen
//    108 breaks the module and Trunk's own download of a prebuilt wasm-opt is not allowed
//    here). Skipped for dev builds and with INTERPOLAB_WASM_OPT=0 (it adds 1.5–3 minutes).
// 2. Every build: stamps the page's two builds (`interpolab`, WebGL2, and `interpolab-webgpu`)
//    into index.html's #interpolab-builds table, which the page's loader reads: a version
//    from the wasm's contents, a query that makes caches fetch a new build since these files
//    keep fixed names. No integrity hash: a fetch with one holds the body back until it is
//    all read and hashed, so the browser cannot compile the wasm while it downloads (the
//    first frame came 10-20 % later, docs/speed.md).
import { spawnSync } from "node:child_process";
import { createHash } from "node:crypto";
import { existsSync, readdirSync, readFileSync, statSync, writeFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const staging = process.env.TRUNK_STAGING_DIR;
if (!staging) {
  console.error("web/wasm-opt.mjs: TRUNK_STAGING_DIR is not set (run it as Trunk's post_build hook)");
  process.exit(1);
}
const wasms = readdirSync(staging).filter((f) => f.endsWith("_bg.wasm"));
if (wasms.length === 0) console.error(`web/wasm-opt.mjs: no *_bg.wasm in ${staging}; nothing to do`);
// The Web Worker's module (`interpolab-worker`) is fetched by its own script, not the page's
// loader; it computes (the simulation, the table rows) and is built for speed.
const isWorker = (name) => name.startsWith("interpolab-worker");

function shrink() {
  if (process.env.TRUNK_PROFILE !== "release") return;
  // A quicker release build for local iterations: INTERPOLAB_WASM_OPT=0 trunk build --release.
  if (process.env.INTERPOLAB_WASM_OPT === "0") {
    console.log("web/wasm-opt.mjs: wasm-opt skipped (INTERPOLAB_WASM_OPT=0); the wasm is not shrunk");
    return;
  }
  const wasmOpt = join(here, "node_modules", ".bin", "wasm-opt");
  if (!existsSync(wasmOpt)) {
    console.error(
      "web/wasm-opt.mjs: wasm-opt is not installed, so the download stays unoptimised " +
        "(about 25% larger); run scripts/setup.sh build (npm binaryen in web/) to install it",
    );
    return;
  }
  for (const name of wasms) {
    const path = join(staging, name);
    const before = statSync(path).size;
    const t0 = Date.now();
    // -Oz: the smallest code; the wasm's own target_features section tells wasm-opt which
    // features (bulk memory, SIMD, …) it may keep using. Names and producers are dropped
    // (no -g). The worker's module is built for speed (Cargo profile worker-release, opt-level
    // 3): -O3 keeps it so.
    const level = isWorker(name) ? "-O3" : "-Oz";
    const run = spawnSync(wasmOpt, [level, "--strip-debug", "--strip-producers", path, "-o", path], {
      stdio: "inherit",
    });
    if (run.status !== 0) {
      console.error(`web/wasm-opt.mjs: wasm-opt failed on ${name} (status ${run.status})`);
      process.exit(1);
    }
    const after = statSync(path).size;
    console.log(`web/wasm-opt.mjs: ${name} ${before} -> ${after} bytes in ${((Date.now() - t0) / 1000).toFixed(1)} s`);
  }
}

function stamp() {
  const builds = {};
  for (const name of wasms.filter((n) => !isWorker(n))) {
    const bytes = readFileSync(join(staging, name));
    builds[name.replace(/_bg\.wasm$/, "")] = { v: createHash("sha256").update(bytes).digest("hex").slice(0, 16) };
  }
  const html = join(staging, "index.html");
  const text = readFileSync(html, "utf8");
  const table = /(<script id="interpolab-builds" type="application\/json">)[^<]*(<\/script>)/;
  if (!table.test(text)) {
    console.error("web/wasm-opt.mjs: index.html has no #interpolab-builds table to stamp");
    process.exit(1);
  }
  writeFileSync(html, text.replace(table, `$1${JSON.stringify(builds)}$2`));
  console.log(`web/wasm-opt.mjs: stamped ${Object.keys(builds).join(", ")} into index.html`);
}

shrink();
stamp();
