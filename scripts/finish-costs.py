#!/usr/bin/env python3
"""What finishing jobs cost: `interpolab finish` on the example scenes with every strategy and on
every finishing scene the fuzzer kept (`target/fuzz/*/case.json`, or the folders given), one
line each with the exit status and the CPU seconds, then a summary: CPU in all, and the
refusals (exit 2) that came after more than a second of CPU, which the fuzz campaign counts
as failures.

    cargo build --release --no-default-features
    python3 scripts/finish-costs.py [--bin target/release/interpolab] [FOLDER ...]

Compare two builds by running it with each `--bin` on the same folders.
"""
import argparse
import glob
import json
import os
import resource
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cases(folders):
    for scene in sorted(glob.glob(os.path.join(ROOT, "examples", "finish", "*.json"))):
        for strategy in ("matched", "ball", "fixed-lead", "principal"):
            yield scene, ["--strategy", strategy]
    for folder in folders:
        for scene in sorted(glob.glob(os.path.join(folder, "*", "case.json"))):
            try:
                with open(scene, encoding="utf-8") as f:
                    if "finish" not in json.load(f):
                        continue
            except (OSError, ValueError):
                continue
            yield scene, []


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=os.path.join(ROOT, "target", "release", "interpolab"))
    ap.add_argument("--limit", type=float, default=60.0, help="CPU seconds a run may take")
    ap.add_argument("folders", nargs="*", default=[os.path.join(ROOT, "target", "fuzz")])
    args = ap.parse_args()
    total, late, runs = 0.0, 0, 0

    def limit():
        resource.setrlimit(resource.RLIMIT_CPU, (int(args.limit), int(args.limit) + 1))

    for scene, extra in cases(args.folders):
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
        p = subprocess.run([args.bin, "finish", scene, *extra], capture_output=True, text=True, preexec_fn=limit)
        cpu = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before
        total += cpu
        runs += 1
        is_late = p.returncode == 2 and cpu > 1.0
        late += is_late
        first = (p.stderr.strip().splitlines() or [""])[0][:120]
        name = os.path.relpath(scene, ROOT)
        print(f"{name} {' '.join(extra)}: exit {p.returncode}, {cpu:.2f} s{'  LATE' if is_late else ''}  {first}", flush=True)
    print(f"{runs} runs, {total:.1f} s of CPU, {late} refused after more than 1 s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
