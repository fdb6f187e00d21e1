#!/usr/bin/env python3
"""Fuzz-style campaign of the command line (issue 11), for as long as wanted.

Mutates the example scenes and finishing scenes (numbers replaced by extreme values, keys
dropped or repeated, bytes flipped) and small G-code programs, runs `run`, `check`, `gcode`,
`steps`, `nurbs`, `finish`, `replay`, `simulate`, `time` and `canon` on them with a time and memory limit, and keeps every case that breaks a promise:
a panic or abort, an exit status other than 0/1/2, a refusal longer than one line or after more
than a second of CPU, NaN/inf/runaway digits in a message, a run past the time limit (30 s of CPU; the wall clock only backs it up, ten times that, so
a campaign holds on a busy machine), a
memory blow-up (address-space limit, 2 GB), or a program the product wrote that `replay` and
`simulate` refuse. Besides mutated scenes and small programs it generates huge programs
(millions of lines, one line of tens of MB) and cutters with extreme body words.

    python3 scripts/fuzz.py --minutes 60 --seed 7 [--bin target/release/interpolab]

Failures go to target/fuzz/<n>/ (input, command, stderr). Exit status 1 if any.
"""
import argparse, json, os, random, re, resource, signal, subprocess, sys, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXTREMES = [0, -0.0, 1, -1, 1e-13, 1e-9, 1e-300, 1e6, 1e12, 1e308, -1e308, 0.5, 3, 360, 99999999, 200000]


def mutate_scene(rng, doc):
    """Replaces one number (or drops/repeats a key) somewhere in the scene."""
    text = json.dumps(doc)
    roll = rng.random()
    nums = list(re.finditer(r"-?\d+(\.\d+)?(e-?\d+)?", text))
    if roll < 0.7 and nums:
        m = rng.choice(nums)
        return text[: m.start()] + repr(rng.choice(EXTREMES)) + text[m.end():]
    keys = list(re.finditer(r'"[a-z_0-9]+": ', text))
    if roll < 0.85 and keys:
        m = rng.choice(keys)
        return text[: m.end()] + "1, " + text[m.start():]  # the key twice
    b = bytearray(text.encode())
    b[rng.randrange(len(b))] = rng.randrange(256)
    return bytes(b)


def gcode(rng):
    lines = ["G90 G21", "G00 X0 Y0 Z5", "G01 F1000"]
    for _ in range(rng.randrange(1, 30)):
        w = rng.choice("XYZIJKRFG")
        v = rng.choice(["1", "-2.5", "0", "9" * rng.choice([3, 40, 400]), "1e5", "0.0000001", "99999999", "6.2", ""])
        lines.append(f"G0{rng.choice('0123')} {w}{v} X{rng.uniform(-50, 50):.3f}")
    return ("\n".join(lines) + "\nM30\n").encode()


def huge_gcode(rng, out):
    """A big program written to a file in the campaign's folder: alternating lines, or one
    enormous line; returns its path."""
    path = os.path.join(out, "huge.nc")
    kind = rng.choice(["lines", "line", "arcs"])
    with open(path, "w") as fh:
        fh.write("G21 G90\nG0 X0 Y0 Z1\nG1 F100\n")
        if kind == "lines":
            fh.write("X1\nX2\n" * rng.choice([100_000, 1_000_000, 2_500_000, 10_000_000]))
        elif kind == "line":
            fh.write("X1 " * rng.choice([1_000_000, 13_000_000]) + "\n")
        else:
            fh.write("G2 X0 Y0 I5 J0\n" * rng.choice([1_000, 100_000, 1_000_000]))
        fh.write("M30\n")
    return path


CUTTERS = ["ball:3", "flat:2", "fillet:5,1", "ball:0", "fillet:1,5", "ball:1e9", "flat:3,flute=10,shank=3:20,holder=10:40",
           "ball:3,flute=1e300", "flat:2,shank=0:5", "flat:2,holder=1e9:1e9", "ball:3,flute=1e-9", "flat:3,nocentre",
           "ball:3,flute=nan", "flat:3,shank=3", "ball:3,lenght=2", "v:3,90,flute=1"]


def limits(mem_mb, cpu_s=None):
    """The child's address space, and its CPU time when given: a run is judged by the CPU it
    takes, so the campaign holds on a machine that is busy with other work."""
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (mem_mb << 20, mem_mb << 20))
        if cpu_s is not None:
            resource.setrlimit(resource.RLIMIT_CPU, (int(cpu_s), int(cpu_s) + 1))
    return apply


# A run's wall-clock backstop, as a multiple of its CPU limit (a busy machine's share).
WALL_OVER_CPU = 10


def child_cpu_s():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def check(bin_, args, timeout_s, mem_mb):
    cpu0 = child_cpu_s()
    try:
        # `canon` prints a line a motion: millions of lines the campaign need not keep.
        out = subprocess.DEVNULL if args[0] == "canon" else subprocess.PIPE
        p = subprocess.run([bin_] + args, stdout=out, stderr=subprocess.PIPE, timeout=WALL_OVER_CPU * timeout_s,
                           preexec_fn=limits(mem_mb, timeout_s))
    except subprocess.TimeoutExpired:
        return f"hang: more than {WALL_OVER_CPU * timeout_s} s of wall clock"
    cpu = child_cpu_s() - cpu0
    err = p.stderr.decode("utf-8", "replace")
    # SIGXCPU at the soft limit, SIGKILL at the hard one.
    if p.returncode in (-signal.SIGXCPU, -signal.SIGKILL) and cpu >= timeout_s - 0.5:
        return f"run past {timeout_s} s of CPU ({cpu:.1f} s)"
    if "panicked" in err or p.returncode not in (0, 1, 2):
        return f"exit {p.returncode}: {err[-500:]}"
    if p.returncode == 2 and len(err.strip().splitlines()) != 1:
        return f"refusal not one line: {err[-500:]}"
    # CPU time, not the wall clock: the campaign may share the machine.
    if p.returncode == 2 and cpu > 1.0:
        return f"refusal after {cpu:.1f} s of CPU: {err[-300:]}"
    if re.search(r"NaN|\binf\b|\d{40}|-0\.0000\b|\x00", err):
        return f"bad value in message: {err[-500:]}"
    return None


# Each kind of case and its share of the rolls: huge generated programs, finishing scenes,
# the other example scenes, small programs.
KINDS = {"huge": (0.0, 0.05), "finish": (0.05, 0.2), "scene": (0.2, 0.7), "gcode": (0.7, 1.0)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--minutes", type=float, default=60)
    ap.add_argument("--seed", type=int, default=int(time.time()))
    ap.add_argument("--bin", default=os.path.join(ROOT, "target/release/interpolab"))
    ap.add_argument("--timeout", type=float, default=30, help="seconds of CPU per command")
    ap.add_argument("--mem-mb", type=int, default=2048, help="address-space limit per command")
    ap.add_argument("--only", choices=sorted(KINDS), help="run one kind of case only (to chase one kind of failure)")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    ex = os.path.join(ROOT, "examples")
    scenes = [json.load(open(os.path.join(ex, f))) for f in sorted(os.listdir(ex)) if f.endswith(".json")]
    fin = os.path.join(ex, "finish")
    finishes = [json.load(open(os.path.join(fin, f))) for f in sorted(os.listdir(fin)) if f.endswith(".json")]
    out = os.path.join(ROOT, "target/fuzz")
    os.makedirs(out, exist_ok=True)
    end, runs, fails = time.time() + 60 * a.minutes, 0, 0
    lo, hi = KINDS[a.only] if a.only else (0.0, 1.0)
    # A campaign stopped early (Ctrl-C, SIGTERM) still says how far it got.
    def stopped(_sig, _frame):
        print(f"stopped: {runs} runs, {fails} failures (seed {a.seed}); failures in {out}", flush=True)
        sys.exit(1 if fails else 0)
    signal.signal(signal.SIGTERM, stopped)
    signal.signal(signal.SIGINT, stopped)
    while time.time() < end:
        if runs and runs % 100 == 0:
            print(f"{runs} runs, {fails} failures so far", flush=True)
        roll = lo + (hi - lo) * rng.random()
        readback = None
        if roll < 0.05:
            # A huge generated program: bounded memory and time, or one line.
            path = huge_gcode(rng, out)
            args = rng.choice([["replay", path], ["simulate", path, "--cutter", "ball:1", "--stock", "-5,-5,-2,10,10,1", "--pitch", "0.2"],
                               ["replay", path, "--scene", os.path.join(ex, "floor-round-wall.json")],
                               ["time", path], ["time", path, "--no-jerk"], ["canon", path]])
            runs += 1
            why = check(a.bin, args, a.timeout, a.mem_mb)
            if why:
                fails += 1
                d = os.path.join(out, str(fails))
                os.makedirs(d, exist_ok=True)
                with open(os.path.join(d, "why.txt"), "w") as fh:
                    fh.write(" ".join(args) + "\n" + why + "\n")
                print(f"FAIL {fails}: {' '.join(args)[:200]}: {why.splitlines()[0][:200]}", flush=True)
            os.remove(path)
            continue
        if roll < 0.2:
            # Seed 001's finishing scenes: the CL data, the comparison table, the program, and
            # the program through the cutting simulation on a coarse grid.
            data, name = mutate_scene(rng, rng.choice(finishes)), "case.json"
            readback = os.path.join(out, "case.nc.out")
            cmds = [["finish", "{f}"], ["finish", "{f}", "--table"], ["finish", "{f}", "--gcode", readback],
                    ["simulate", "{f}", "--finish", "0.005", "--pitch=" + rng.choice(["0.5", "1", "1e-9", "-1", "1e9"])]]
        elif roll < 0.7:
            data, name = mutate_scene(rng, rng.choice(scenes)), "case.json"
            cmds = [["run", "{f}"], ["check", "{f}"], ["steps", "{f}", "--tolerance", "0.01"],
                    ["gcode", "{f}", "--kind", rng.choice(["g01", "arcs", "nurbs"]), "--tolerance", "0.01"],
                    ["nurbs", "{f}", "--tolerance", "0.01"]]
        else:
            data, name = gcode(rng), "case.nc"
            cmds = [["replay", "{f}"], ["replay", "{f}", "--scene", os.path.join(ex, "floor-round-wall.json")],
                    ["time", "{f}", "--machine", rng.choice(["vmc", "hobby-router", "table-ac"])] + rng.choice([[], ["--no-jerk"], ["--exact-stop"]]),
                    ["time", "{f}", "--periods", os.path.join(out, "periods.csv")],
                    ["simulate", "{f}", "--cutter", rng.choice(CUTTERS), "--crashes", os.path.join(out, "crashes.csv"),
                     "--stock", rng.choice(["-60,-60,-10,60,60,10", "0,0,0,0,0,0", "-1e9,-1e9,0,1e9,1e9,1"]),
                     "--pitch=" + rng.choice(["0.5", "0.05", "0", "nan", "-2"])]]
        path = os.path.join(out, name)
        with open(path, "wb") as fh:
            fh.write(data if isinstance(data, bytes) else data.encode())
        args = [x.replace("{f}", path) for x in rng.choice(cmds)]
        runs += 1
        if readback and os.path.exists(readback):
            os.remove(readback)
        why = check(a.bin, args, a.timeout, a.mem_mb)
        # A program the product wrote is read back by replay and simulate.
        if not why and readback and "--gcode" in args and os.path.exists(readback):
            for back in (["replay", readback], ["simulate", readback, "--cutter", "ball:3", "--stock", "-100,-100,-100,100,100,100", "--pitch", "2"]):
                p = subprocess.run([a.bin] + back, capture_output=True, timeout=WALL_OVER_CPU * a.timeout,
                                   preexec_fn=limits(a.mem_mb, a.timeout))
                if p.returncode not in (0, 1):
                    why = f"the written program is refused by {back[0]}: {p.stderr.decode('utf-8', 'replace')[-300:]}"
                    break
        if why:
            fails += 1
            d = os.path.join(out, str(fails))
            os.makedirs(d, exist_ok=True)
            os.replace(path, os.path.join(d, name))
            with open(os.path.join(d, "why.txt"), "w") as fh:
                fh.write(" ".join(args) + "\n" + why + "\n")
            print(f"FAIL {fails}: {' '.join(args)}: {why.splitlines()[0][:200]}", flush=True)
    print(f"{runs} runs, {fails} failures (seed {a.seed}); failures in {out}")
    sys.exit(1 if fails else 0)


if __name__ == "__main__":
    main()
