#!/usr/bin/env python3
"""Anchors of the feed planner (issue 23): the time-optimal path parameterisation under the
same velocity and acceleration limits — TOPP-RA (Pham & Pham, IEEE T-RO 34(3), 2018;
PyPI `toppra`, installed here in a venv) — is a lower bound no plan may beat, and on
jerk-free settings the planner must be within 5 % of it.

For every example program and machine this script runs `interpolab time … --geometry`,
which writes the path the plan follows (s, q, q', q'' of the six joints, the programmed
feed cap, zero where the path stops), hands exactly those samples to TOPP-RA as its grid
(the joints' velocity and acceleration limits; the feed as a seventh "joint" q7 with
q7' = F_ref / F(s) and limit F_ref), and compares. It also re-checks every printed period
of the jerk-limited plan against the joint limits by differences (its own code, not the
planner's), and writes tests/data/plan/topp_bounds.csv for `cargo test --test plan_topp`.

    python3 scripts/plan-anchors.py [--binary target/release/interpolab] [--quick]

Exit status 1 when a plan beats the bound, a jerk-free plan is more than 5 % above it, or
a printed period breaks a limit.
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VENV = os.path.join(ROOT, "target", "venv-toppra")
DATA = os.path.join(ROOT, "tests", "data", "plan")


def ensure_venv():
    py = os.path.join(VENV, "bin", "python")
    if not os.path.exists(py):
        subprocess.check_call([sys.executable, "-m", "venv", VENV])
    try:
        subprocess.check_call([py, "-c", "import toppra"], stderr=subprocess.DEVNULL)
    except subprocess.CalledProcessError:
        subprocess.check_call([py, "-m", "pip", "install", "-q", "toppra==0.6.10"])
    return py


TOPP = r'''
import csv, sys, numpy as np, toppra as ta, toppra.constraint as constraint, toppra.algorithm as algo
ta.setup_logging("WARNING")
rows = list(csv.reader(open(sys.argv[1])))[1:]
data = np.array([[float(x) for x in r] for r in rows])
v = [float(x) for x in sys.argv[2].split(",")]
a = [float(x) for x in sys.argv[3].split(",")]
ss = data[:, 0]
keep = np.concatenate([[True], np.diff(ss) > 1e-9])
data = data[keep]; ss = data[:, 0]
q, dq, ddq, feed = data[:, 1:7], data[:, 7:13], data[:, 13:19], data[:, 19]
finite = feed[(feed > 0) & (feed < 1e8)]
fref = float(finite.max()) if len(finite) else 1.0
q7d = np.full(len(feed), 1e9)
np.divide(fref, feed, out=q7d, where=feed > 0)
q7 = np.concatenate([[0.0], np.cumsum(np.diff(ss) * q7d[:-1])])
Q = np.column_stack([q, q7]); DQ = np.column_stack([dq, q7d]); DDQ = np.column_stack([ddq, np.zeros(len(ss))])

class Table(ta.interpolator.AbstractGeometricPath):
    def __call__(self, s, order=0):
        s = np.atleast_1d(s)
        i = np.clip(np.searchsorted(ss, s - 1e-12), 0, len(ss) - 1)
        return (Q, DQ, DDQ)[order][i]
    @property
    def dof(self):
        return 7
    @property
    def path_interval(self):
        return np.array([ss[0], ss[-1]])
    @property
    def waypoints(self):
        return ss, Q

vl = np.array([[-x, x] for x in v + [fref]])
al = np.array([[-x, x] for x in a + [1e12]])
inst = algo.TOPPRA([constraint.JointVelocityConstraint(vl), constraint.JointAccelerationConstraint(al)],
                   Table(), gridpoints=ss, parametrizer="ParametrizeConstAccel")
res = inst.compute_parameterization(0, 0)
sd = res[1]
if sd is None:
    print("nan"); sys.exit(0)
sd = np.maximum(np.asarray(sd, dtype=float), 0.0)  # toppra gives the speed sdot itself
ds = np.diff(ss)
den = sd[:-1] + sd[1:]
print(float(np.sum(np.where(den > 0, 2 * ds / np.maximum(den, 1e-300), 0.0))))
'''

MACHINES = {
    # joint limits in planner units (mm/s, mm/s², rad/s, rad/s²) as the presets give them
    "vmc": ([500, 500, 400] + [7200 / 60 * 3.141592653589793 / 180] * 3, [3000, 3000, 3000] + [900 * 3.141592653589793 / 180] * 3),
    "hobby-router": ([5000 / 60, 5000 / 60, 2000 / 60] + [3600 / 60 * 3.141592653589793 / 180] * 3, [300, 300, 150] + [300 * 3.141592653589793 / 180] * 3),
    "table-ac": ([500, 500, 400, 5400 / 60 * 3.141592653589793 / 180, 7200 / 60 * 3.141592653589793 / 180, 7200 / 60 * 3.141592653589793 / 180],
                 [3000, 3000, 3000, 600 * 3.141592653589793 / 180, 900 * 3.141592653589793 / 180, 900 * 3.141592653589793 / 180]),
}
JERK = {"vmc": [50000, 50000, 50000] + [9000 * 3.141592653589793 / 180] * 3,
        "hobby-router": [3000, 3000, 1500] + [3000 * 3.141592653589793 / 180] * 3,
        "table-ac": [50000, 50000, 50000, 6000 * 3.141592653589793 / 180, 9000 * 3.141592653589793 / 180, 9000 * 3.141592653589793 / 180]}


def run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: {out.stderr.strip()}")
    return out.stdout


def planned_time(text):
    """The planned motion time: the total less the dwells (TOPP-RA knows no dwell)."""
    for line in text.splitlines():
        if line.startswith("time"):
            w = line.replace("(", " ").replace(")", " ").replace(",", " ").split()
            return float(w[1]) - float(w[w.index("dwell") + 1])
    raise SystemExit("no time line")


# Allowance for the positions' own rounding: an error eps in each printed position gives up
# to 2^n eps / Ts^n in the n-th difference (eps = 1e-10 mm: 2e-7 mm/s, 4e-4 mm/s², 0.8 mm/s³).
EPS = 1e-10
# How far below TOPP-RA's gridded time a plan may come (relative) before it is said to beat
# the bound: the grid's own error, measured by halving the spacing (docs/feed-planning.md).
RTOL = 2e-4


def check_periods(path, machine, jerk=True):
    v, a = MACHINES[machine]
    j = JERK[machine] if jerk else [float("inf")] * 6
    ts = 0.001
    worst = 0.0
    prev = []
    deg = 3.141592653589793 / 180
    with open(path) as f:
        r = csv.reader(f)
        next(r)
        for row in r:
            q = [float(x) for x in row[2:8]]
            q = q[:3] + [x * deg for x in q[3:]]
            prev.append(q)
            if len(prev) > 4:
                prev.pop(0)
            n = len(prev)
            for i in range(6):
                if n >= 2:
                    d1 = abs(prev[-1][i] - prev[-2][i]) / ts
                    worst = max(worst, max(0.0, d1 - 2 * EPS / ts) / v[i])
                if n >= 3:
                    d2 = abs(prev[-1][i] - 2 * prev[-2][i] + prev[-3][i]) / ts**2
                    worst = max(worst, max(0.0, d2 - 4 * EPS / ts**2) / a[i])
                if n >= 4:
                    d3 = abs(prev[-1][i] - 3 * prev[-2][i] + 3 * prev[-3][i] - prev[-4][i]) / ts**3
                    worst = max(worst, max(0.0, d3 - 8 * EPS / ts**3) / j[i])
    return worst


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "interpolab"))
    ap.add_argument("--quick", action="store_true", help="fewer examples")
    ap.add_argument("--step", type=float, default=0.05, help="TOPP-RA grid spacing (mm)")
    args = ap.parse_args()
    py = ensure_venv()
    b = args.binary
    tmp = tempfile.mkdtemp(prefix="plan-anchors-")
    programs = []
    for kind in ["g01", "arcs", "nurbs"]:
        out = os.path.join(tmp, f"parabola-{kind}.nc")
        run([b, "gcode", "--profile", "parabola", "--kind", kind, "--tolerance", "0.01", "--out", out])
        programs.append((f"parabola {kind}", out))
        fast = os.path.join(tmp, f"parabola6000-{kind}.nc")
        run([b, "gcode", "--profile", "parabola", "--kind", kind, "--tolerance", "0.01", "--feed", "6000", "--out", fast])
        programs.append((f"parabola6000 {kind}", fast))
    scenes = ["torus-plane", "sphere-plane"] if not args.quick else ["torus-plane"]
    for sc in scenes:
        for kind in ["g01", "arcs", "nurbs"]:
            out = os.path.join(tmp, f"{sc}-{kind}.nc")
            run([b, "gcode", os.path.join(ROOT, "examples", f"{sc}.json"), "--kind", kind, "--tolerance", "0.01", "--out", out])
            programs.append((f"{sc} {kind}", out))
    for name in sorted(os.listdir(DATA)):
        if name.endswith(".nc"):
            programs.append((name[:-3], os.path.join(DATA, name)))
    rows = []
    failed = False
    print("| program | machine | TOPP-RA s | jerk-free plan s | ratio | jerk-limited plan s | periods within limits |")
    print("|---|---|---:|---:|---:|---:|---|")
    for label, prog in programs:
        for m in (["vmc", "hobby-router"] if "5axis" not in label else ["table-ac"]):
            g = os.path.join(tmp, "g.csv")
            per_free = os.path.join(tmp, "pf.csv")
            t_free = planned_time(run([b, "time", prog, "--machine", m, "--no-jerk", "--geometry", g,
                                       "--geometry-step", str(args.step), "--periods", per_free]))
            worst_free = check_periods(per_free, m, jerk=False)
            v, a = MACHINES[m]
            bound = float(subprocess.run([py, "-c", TOPP, g, ",".join(map(str, v)), ",".join(map(str, a))],
                                         capture_output=True, text=True, check=True).stdout.strip())
            per = os.path.join(tmp, "p.csv")
            t_jerk = planned_time(run([b, "time", prog, "--machine", m, "--periods", per]))
            worst = max(check_periods(per, m), worst_free)
            ratio = t_free / bound
            # TOPP-RA's grid leaves it a little above the continuous optimum (its first
            # interval from rest, its switch points on grid points); RTOL is that margin.
            ok = bound * (1 - RTOL) <= t_free and ratio <= 1.05 and t_jerk >= bound * (1 - RTOL) and worst <= 1 + 1e-9
            failed |= not ok
            rows.append((label, m, bound))
            print(f"| {label} | {m} | {bound:.4f} | {t_free:.4f} | {ratio:.5f} | {t_jerk:.4f} | {worst:.6f}{'' if ok else ' FAIL'} |")
    os.makedirs(DATA, exist_ok=True)
    with open(os.path.join(DATA, "topp_bounds.csv"), "w") as f:
        f.write("program,machine,topp_ra_s\n")
        for label, m, bound in rows:
            f.write(f"{label},{m},{bound!r}\n")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
