#!/usr/bin/env python3
"""Prints the README's table of nanoseconds per period from criterion's results.

Run `cargo bench --no-default-features --bench crease` first; this reads
target/criterion/<scene>/<method>/new/estimates.json (mean time of one iteration of
PERIODS periods, see benches/crease.rs).
"""
import json
import pathlib
import platform
import subprocess

PERIODS = 500
SCENES = ["floor-round-wall", "sphere-plane", "crossing-cylinders", "torus-plane",
          "bspline-floor-wall", "rational-nurbs-vault"]
root = pathlib.Path(__file__).resolve().parent.parent / "target" / "criterion"


def ns_per_period(scene, method):
    est = json.loads((root / scene / method / "new" / "estimates.json").read_text())
    return est["mean"]["point_estimate"] / PERIODS


cpu = "unknown CPU"
try:
    for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
except OSError:
    pass
cores = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
rustc = subprocess.run(["rustc", "--version"], capture_output=True, text=True).stdout.strip()
print(f"Machine: {cpu}, {cores} cores, {platform.system()} {platform.machine()}; {rustc}; release profile.\n")
print("| scene | surfaces | seed 000 (ns/period) | exact Newton (ns/period) | exact / seed 000 |")
print("|---|---|---:|---:|---:|")
kinds = {
    "floor-round-wall": "plane + cylinder", "sphere-plane": "sphere + plane",
    "crossing-cylinders": "cylinder + cylinder", "torus-plane": "torus + plane",
    "bspline-floor-wall": "bicubic B-spline + plane", "rational-nurbs-vault": "rational NURBS + plane",
}
for s in SCENES:
    a, b = ns_per_period(s, "seed000"), ns_per_period(s, "exact")
    print(f"| {s} | {kinds[s]} | {a:.0f} | {b:.0f} | {b / a:.1f}× |")
