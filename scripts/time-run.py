#!/usr/bin/env python3
"""End-to-end time of `interpolab run SCENE > /dev/null` per example (the whole process, as a
user runs it): the median and minimum wall time of N runs (default 20), and the median CPU
time (user + system), which a busy shared machine disturbs less than the wall time.

    scripts/time-run.py [BINARY] [N]     # BINARY defaults to target/release/interpolab
"""
import glob
import os
import resource
import statistics
import subprocess
import sys
import time

binary = sys.argv[1] if len(sys.argv) > 1 else "target/release/interpolab"
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 20
os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
print(f"{'example':<28} {'rows':>6} {'median ms':>10} {'min ms':>8} {'cpu ms':>8}")
for scene in sorted(glob.glob("examples/*.json")):
    times, cpu = [], []
    for _ in range(runs):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run([binary, "run", scene], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        times.append((time.perf_counter() - t0) * 1000.0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append((r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime) * 1000.0)
    rows = subprocess.run([binary, "run", scene], capture_output=True, check=True).stdout.count(b"\n") - 1
    name = os.path.basename(scene)
    print(f"{name:<28} {rows:>6} {statistics.median(times):>10.2f} {min(times):>8.2f} {statistics.median(cpu):>8.2f}")
