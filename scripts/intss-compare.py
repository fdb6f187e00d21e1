#!/usr/bin/env python3
"""`interpolab run` against OpenCASCADE's GeomAPI_IntSS, per scene, in one run.

A user who wants the path of a ball's centre along the crease of two surfaces could instead
intersect the two surfaces offset by the ball's radius with OpenCASCADE. This script builds,
for each of nine scenes (the seven examples and two more of the same kind, written to
target/intss/), the two offset surfaces exactly as interpolab defines them (docs/scene-format.md,
src/geom/surface.rs), times GeomAPI_IntSS on them (median of --reps constructions) and the
whole `interpolab run SCENE > /dev/null` process (median of --runs), and prints the ratio.

It also checks that the two compute the same curve, so the comparison is honest: sample rows of
`run` (the timed, default method) and of `run --method exact` are projected onto the IntSS
curves, and points of the IntSS curves are projected onto the two base surfaces (their
distance must be R').

OpenCASCADE comes from PyPI's `cadquery-ocp` (and its dependencies), installed once into a
virtual environment under target/intss-venv; set PIP_FIND_LINKS to a directory holding the
downloaded wheel to avoid fetching it again. A benchmark tool only: not part of
scripts/test.sh.

    scripts/intss-compare.py [--binary target/release/interpolab] [--runs 21] [--reps 11]
"""
import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
VENV = os.path.join(ROOT, "target", "intss-venv")
OCP_REQ = "cadquery-ocp==8.0.1.1.0"


def ensure_venv():
    """Re-executes this script inside the venv holding OCP, creating it first if needed."""
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
    probe = subprocess.run([py, "-c", "import OCP.GeomAPI"], capture_output=True)
    if probe.returncode != 0:
        subprocess.run([py, "-m", "pip", "install", "--quiet", OCP_REQ], check=True)
    os.execv(py, [py, os.path.abspath(__file__)] + sys.argv[1:])


# The two scenes added to the seven examples: a bicubic floor with a wall (like
# bspline-floor-wall, with a one-span patch) and a post standing on a dome.
EXTRA_SCENES = {
    "bicubic-floor-wall": {
        "format": "interpolab-scene/1",
        "name": "Bicubic floor and a straight wall (IntSS comparison)",
        "surfaces": [
            {
                "type": "nurbs",
                "degree": [3, 3],
                "knots_u": [0, 0, 0, 0, 1, 1, 1, 1],
                "knots_v": [0, 0, 0, 0, 1, 1, 1, 1],
                "points": [
                    [[0, 0, 0], [0, 26.666667, 3], [0, 53.333333, 2], [0, 80, 0]],
                    [[33.333333, 0, 4], [33.333333, 26.666667, 8], [33.333333, 53.333333, 7], [33.333333, 80, 3]],
                    [[66.666667, 0, 2], [66.666667, 26.666667, 6], [66.666667, 53.333333, 6], [66.666667, 80, 2]],
                    [[100, 0, 0], [100, 26.666667, 2], [100, 53.333333, 3], [100, 80, 1]],
                ],
            },
            {
                "type": "plane",
                "origin": [70, 0, 0],
                "normal": [-1, 0, 0],
                "u_axis": [0, 1, 0],
                "domain": {"u": [-10, 90], "v": [-40, 10]},
            },
        ],
        "tool": {"radius": 3.0, "allowance": 0.0},
        "motion": {"feed": 1500.0, "period": 4.0},
        "tolerance": {"t1": 0.01, "t2": 0.01, "share": 0.5},
        "path": {"start": [67.0, 5.0, 7.0], "end": [67.0, 75.0, 7.0], "direction": [0, 1, 0], "max_steps": 200000},
    },
    "sphere-cylinder": {
        "format": "interpolab-scene/1",
        "name": "A post on a dome (sphere and cylinder, IntSS comparison)",
        "surfaces": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 40.0, "normal": "outward"},
            {
                "type": "cylinder",
                "origin": [0, 0, 0],
                "axis": [0, 0, 1],
                "radius": 25.0,
                "domain": {"u": [0, 360], "v": [0, 80]},
                "normal": "outward",
            },
        ],
        "tool": {"radius": 5.0, "allowance": 0.0},
        "motion": {"feed": 1500.0, "period": 4.0},
        "tolerance": {"t1": 0.01, "t2": 0.01, "share": 0.5},
        "path": {"start": [30.0, 0.0, 33.5], "end": None, "max_steps": 200000},
    },
}


def scenes():
    """(name, path, parsed JSON) of the nine scenes, sorted by name."""
    out = []
    ex = os.path.join(ROOT, "examples")
    for f in sorted(os.listdir(ex)):
        if f.endswith(".json"):
            p = os.path.join(ex, f)
            with open(p) as fh:
                out.append((f[:-5], p, json.load(fh)))
    gen = os.path.join(ROOT, "target", "intss")
    os.makedirs(gen, exist_ok=True)
    for name, scene in EXTRA_SCENES.items():
        p = os.path.join(gen, name + ".json")
        with open(p, "w") as fh:
            json.dump(scene, fh, indent=2)
        out.append((name, p, scene))
    return sorted(out)


def main():
    ensure_venv()
    import math
    import statistics
    import time

    from OCP.Geom import (
        Geom_BSplineSurface,
        Geom_CylindricalSurface,
        Geom_OffsetSurface,
        Geom_Plane,
        Geom_RectangularTrimmedSurface,
        Geom_SphericalSurface,
        Geom_ToroidalSurface,
    )
    from OCP.GeomAPI import GeomAPI_IntSS, GeomAPI_ProjectPointOnCurve, GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt
    # OCCT 8's NCollection arrays (TColgp_Array2OfPnt, TColStd_Array1OfReal, ... before).
    from OCP.collections import Array1_double, Array1_int, Array2_double, Array2_gp_Pnt

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "interpolab"))
    ap.add_argument("--runs", type=int, default=21, help="runs of the interpolab process per scene")
    ap.add_argument("--reps", type=int, default=11, help="GeomAPI_IntSS constructions per scene")
    ap.add_argument("--tol", type=float, default=1e-7, help="IntSS tolerance (mm); Precision::Confusion")
    ap.add_argument("--scene", action="append", help="only these scenes (names)")
    args = ap.parse_args()

    def unit(v):
        n = math.sqrt(sum(x * x for x in v))
        return [x / n for x in v]

    def dot(a, b):
        return sum(x * y for x, y in zip(a, b))

    def any_perpendicular(a):
        # src/geom/frame.rs: the world axis least aligned with a, its axial part removed.
        ax = [abs(x) for x in a]
        if ax[0] <= ax[1] and ax[0] <= ax[2]:
            w = [1.0, 0.0, 0.0]
        elif ax[1] <= ax[2]:
            w = [0.0, 1.0, 0.0]
        else:
            w = [0.0, 0.0, 1.0]
        d = dot(w, a)
        return unit([w[i] - a[i] * d for i in range(3)])

    def ax3(origin, axis, ref):
        a = unit(axis)
        e1 = any_perpendicular(a) if ref is None else unit([ref[i] - a[i] * dot(ref, a) for i in range(3)])
        # Right-handed (e1, a × e1, a), as src/geom/frame.rs: OCC's natural normal r_u × r_v
        # is then the same as interpolab's parametrisation normal.
        return gp_Ax3(gp_Pnt(*origin), gp_Dir(*a), gp_Dir(*e1))

    def flat_knots(knots):
        distinct, mults = [], []
        for k in knots:
            if distinct and k == distinct[-1]:
                mults[-1] += 1
            else:
                distinct.append(float(k))
                mults.append(1)
        ka = Array1_double(1, len(distinct))
        ma = Array1_int(1, len(mults))
        for i, (k, m) in enumerate(zip(distinct, mults)):
            ka.SetValue(i + 1, k)
            ma.SetValue(i + 1, m)
        return ka, ma

    def base_surface(s):
        """(Geom surface, sign of the cutter side relative to r_u × r_v, trim or None)."""
        t = s["type"]
        sign = -1.0 if s.get("normal") == "inward" else 1.0
        if t == "plane":
            d = s["domain"]
            return Geom_Plane(ax3(s["origin"], s["normal"], s["u_axis"])), 1.0, (d["u"], d["v"])
        if t == "cylinder":
            d = s["domain"]
            u = None if d["u"][1] - d["u"][0] >= 360 else [math.radians(x) for x in d["u"]]
            g = Geom_CylindricalSurface(ax3(s["origin"], s["axis"], s.get("ref_dir")), s["radius"])
            return g, sign, (u, d["v"])
        if t == "sphere":
            d = s.get("domain")
            g = Geom_SphericalSurface(ax3(s["center"], s.get("axis", [0, 0, 1]), s.get("ref_dir")), s["radius"])
            trim = None if d is None else ([math.radians(x) for x in d["u"]], [math.radians(x) for x in d["v"]])
            return g, sign, trim
        if t == "torus":
            d = s.get("domain")
            g = Geom_ToroidalSurface(
                ax3(s["center"], s["axis"], s.get("ref_dir")), s["major_radius"], s["minor_radius"]
            )
            trim = None if d is None else ([math.radians(x) for x in d["u"]], [math.radians(x) for x in d["v"]])
            return g, sign, trim
        if t == "nurbs":
            pts = s["points"]
            nu, nv = len(pts), len(pts[0])
            poles = Array2_gp_Pnt(1, nu, 1, nv)
            weights = Array2_double(1, nu, 1, nv)
            w = s.get("weights")
            for i in range(nu):
                for j in range(nv):
                    poles.SetValue(i + 1, j + 1, gp_Pnt(*pts[i][j]))
                    weights.SetValue(i + 1, j + 1, float(w[i][j]) if w else 1.0)
            uk, um = flat_knots(s["knots_u"])
            vk, vm = flat_knots(s["knots_v"])
            g = Geom_BSplineSurface(poles, weights, uk, vk, um, vm, s["degree"][0], s["degree"][1], False, False)
            return g, (-1.0 if s.get("flip_normal") else 1.0), None
        raise SystemExit(f"unknown surface type {t}")

    def offset_surface(s, r_eff):
        g, sign, trim = base_surface(s)
        off = Geom_OffsetSurface(g, sign * r_eff)
        if trim is None:
            return g, off
        u, v = trim
        if u is None:
            return g, Geom_RectangularTrimmedSurface(off, float(v[0]), float(v[1]), False)
        return g, Geom_RectangularTrimmedSurface(off, float(u[0]), float(u[1]), float(v[0]), float(v[1]))

    def rows_of(cmd):
        out = subprocess.run(cmd, capture_output=True, check=True, text=True).stdout.splitlines()
        return [[float(x) for x in line.split(",")[2:5]] for line in out[1:]]

    devnull = os.open(os.devnull, os.O_WRONLY)
    actions = [(os.POSIX_SPAWN_DUP2, devnull, 1), (os.POSIX_SPAWN_DUP2, devnull, 2)]

    def run_once(argv):
        """Wall time (ms) of one whole process, started as a shell would (posix_spawn, output
        to /dev/null), so that Python's own overhead stays small."""
        t0 = time.perf_counter()
        pid = os.posix_spawn(argv[0], argv, os.environ, file_actions=actions)
        _, status = os.waitpid(pid, 0)
        ms = (time.perf_counter() - t0) * 1000.0
        if os.waitstatus_to_exitcode(status) != 0:
            raise SystemExit(f"{' '.join(argv)} failed")
        return ms

    print(f"OpenCASCADE GeomAPI_IntSS (cadquery-ocp {OCP_REQ.split('==')[1]}, tol {args.tol:g} mm, median of "
          f"{args.reps}) vs `{os.path.relpath(args.binary, ROOT)} run SCENE > /dev/null` (wall, median of "
          f"{args.runs}), interleaved; load average {os.getloadavg()[0]:.1f}")
    # floor: `interpolab --version` (process start and exit); IntSS/floor is the most any
    # `run` could reach. row→IntSS: largest distance of 9 rows of `run` (and of `run --method
    # exact`) to the IntSS curves; IntSS→R′: largest | distance − R′ | of IntSS curve points
    # to the two base surfaces.
    hdr = (f"{'scene':<22} {'rows':>5} {'IntSS ms':>9} {'run ms':>7} {'ratio':>6} {'floor ms':>8} {'ratio≤':>7} "
           f"{'lines':>5} {'row→IntSS mm':>12} {'exact→IntSS mm':>14} {'IntSS→R′ mm':>11}")
    print(hdr)
    ratios = []
    for name, path, scene in scenes():
        if args.scene and name not in args.scene:
            continue
        r_eff = scene["tool"]["radius"] + scene["tool"].get("allowance", 0.0)
        (b1, o1), (b2, o2) = (offset_surface(s, r_eff) for s in scene["surfaces"])
        # Interleaved, so that the load of a shared machine falls on both alike: one IntSS,
        # one whole `run` process, one `--version` process (the floor: start and exit alone).
        t_occ, t_run, t_floor, inter = [], [], [], None
        for i in range(max(args.reps, args.runs)):
            if i < args.reps:
                t0 = time.perf_counter()
                inter = GeomAPI_IntSS(o1, o2, args.tol)
                t_occ.append((time.perf_counter() - t0) * 1000.0)
            if i < args.runs:
                t_run.append(run_once([args.binary, "run", path]))
                t_floor.append(run_once([args.binary, "--version"]))
        if not inter.IsDone() or inter.NbLines() == 0:
            raise SystemExit(f"{name}: GeomAPI_IntSS found no curve")
        lines = [inter.Line(i) for i in range(1, inter.NbLines() + 1)]
        t_intss = statistics.median(t_occ)

        def to_intss(p):
            best = math.inf
            for c in lines:
                pr = GeomAPI_ProjectPointOnCurve(gp_Pnt(*p), c)
                if pr.NbPoints() > 0:
                    best = min(best, pr.LowerDistance())
            return best

        rows = rows_of([args.binary, "run", path])
        exact = rows_of([args.binary, "run", "--method", "exact", path])
        picks = lambda rs: [rs[i * (len(rs) - 1) // 8] for i in range(9)]  # noqa: E731
        d_rows = max(to_intss(p) for p in picks(rows))
        d_exact = max(to_intss(p) for p in picks(exact))
        # Points of the IntSS curves are at R' from both base surfaces (within the interval
        # of each line; lines may extend past where `run` stops, at a domain's edge).
        d_off = 0.0
        for c in lines:
            a, b = c.FirstParameter(), c.LastParameter()
            for i in range(5):
                p = c.Value(a + (b - a) * (i + 0.5) / 5)
                for g in (b1, b2):
                    pr = GeomAPI_ProjectPointOnSurf(p, g)
                    if pr.NbPoints() > 0:
                        d_off = max(d_off, abs(pr.LowerDistance() - r_eff))
        allowed = max(scene["tolerance"]["share"] * scene["tolerance"][k] for k in ("t1", "t2"))
        if d_rows > allowed or d_exact > 1e-3 or d_off > 1e-3:
            raise SystemExit(f"{name}: the IntSS curve does not match the crease "
                             f"(rows {d_rows:.2e}, exact {d_exact:.2e}, offset {d_off:.2e} mm)")
        t_run, t_floor = statistics.median(t_run), statistics.median(t_floor)
        ratios.append(t_intss / t_run)
        print(f"{name:<22} {len(rows) - 1:>5} {t_intss:>9.2f} {t_run:>7.2f} {t_intss / t_run:>6.1f} {t_floor:>8.2f} "
              f"{t_intss / t_floor:>7.1f} {len(lines):>5} {d_rows:>12.1e} {d_exact:>14.1e} {d_off:>11.1e}", flush=True)
    if ratios:
        gm = math.exp(sum(math.log(r) for r in ratios) / len(ratios))
        print(f"ratio IntSS / run: min {min(ratios):.1f}, geometric mean {gm:.1f}, max {max(ratios):.1f}")


if __name__ == "__main__":
    main()
