// Compares two screenshots pixel by pixel (same size): how many pixels differ, the largest
// difference of a channel, and the bounding box of the differing pixels. A measuring aid for
// variants that should look the same (`frame-profile.mjs --shots`), not a test.
//
//   node e2e/png-diff.mjs A.png B.png [--tolerance 0] [--out DIFF.png]
// --out: A with every differing pixel painted magenta.
// --crop X,Y,W,H --side OUT.png: that rectangle of A, of B and of the marked A side by side,
// each enlarged twice (to look at small text).
import fs from "node:fs";
import { PNG } from "pngjs";

const args = process.argv.slice(2);
const [fa, fb] = args.filter((a) => a.endsWith(".png"));
const tol = args.includes("--tolerance") ? Number(args[args.indexOf("--tolerance") + 1]) : 0;
const a = PNG.sync.read(fs.readFileSync(fa));
const b = PNG.sync.read(fs.readFileSync(fb));
if (a.width !== b.width || a.height !== b.height) {
  console.log(`sizes differ: ${a.width}×${a.height} against ${b.width}×${b.height}`);
  process.exit(1);
}
const out = args.includes("--out") ? args[args.indexOf("--out") + 1] : null;
let n = 0;
let worst = 0;
const box = [Infinity, Infinity, -Infinity, -Infinity];
for (let y = 0; y < a.height; y++) {
  for (let x = 0; x < a.width; x++) {
    const i = 4 * (y * a.width + x);
    let d = 0;
    for (let c = 0; c < 4; c++) d = Math.max(d, Math.abs(a.data[i + c] - b.data[i + c]));
    if (d > tol) {
      n++;
      worst = Math.max(worst, d);
      box[0] = Math.min(box[0], x);
      box[1] = Math.min(box[1], y);
      box[2] = Math.max(box[2], x);
      box[3] = Math.max(box[3], y);
      if (out) a.data.set([255, 0, 255, 255], i);
    }
  }
}
const side = args.includes("--side") ? args[args.indexOf("--side") + 1] : null;
if (side && args.includes("--crop")) {
  const [cx, cy, cw, ch] = args[args.indexOf("--crop") + 1].split(",").map(Number);
  const marked = PNG.sync.read(PNG.sync.write(a));
  const originalA = PNG.sync.read(fs.readFileSync(fa));
  const k = 2;
  const s = new PNG({ width: 3 * cw * k, height: ch * k });
  [originalA, b, marked].forEach((img, panel) => {
    for (let y = 0; y < ch * k; y++) {
      for (let x = 0; x < cw * k; x++) {
        const sx = Math.min(img.width - 1, cx + Math.floor(x / k));
        const sy = Math.min(img.height - 1, cy + Math.floor(y / k));
        const from = 4 * (sy * img.width + sx);
        const to = 4 * (y * s.width + panel * cw * k + x);
        for (let c = 0; c < 4; c++) s.data[to + c] = img.data[from + c];
      }
    }
  });
  fs.writeFileSync(side, PNG.sync.write(s));
}
if (out) fs.writeFileSync(out, PNG.sync.write(a));
console.log(JSON.stringify({ differing_pixels: n, largest_channel_difference: worst, box: n ? box : null }));
