#!/usr/bin/env python3
"""Reads a directory of real G-code programs with ours and with LinuxCNC's `rs274` (issue 21).

For every program under DIR (recursively; .nc .ngc .gcode .tap .cnc .txt .mpf .ptp .iso .eia
.min .h and upper-case forms; LinuxCNC subroutine files — first code line `o<name> sub` with
the file's own name — are left out, they are found by the programs that call them):

- `BINARY replay FILE`: exit 0 read completely, 1 read with words left out (UNSUPPORTED lines,
  counted), 2 refused (the first line of its message), anything else (a signal, a panic, the
  time or memory limit) crashed; and the number of motions it reports.
- `rs274 -g FILE`: read to the end (exit 0) or stopped at an error: the line (from a numbered
  copy of the program, as tests/support/rs274.rs does) and LinuxCNC's message; and the number of
  motions it printed. The program's own directory is its subroutine path, and a tool table
  with tools 1-999 of zero length stands in for the machine's (rs274 refuses tools it does not
  know).

Each run is limited to 30 s and 2 GB of address space (as scripts/fuzz.py does), and gets its
own HOME (rs274 keeps its tool data in $HOME/.tool.mmap).

    python3 scripts/corpus.py DIR [--binary target/release/interpolab] [--json OUT] [--jobs 2] [--ext .ngc]

Prints a Markdown table, one row a program, then the totals.
"""
import argparse, concurrent.futures, json, os, re, resource, shutil, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXTENSIONS = {".nc", ".ngc", ".gcode", ".tap", ".cnc", ".txt", ".mpf", ".ptp", ".iso", ".eia", ".min", ".h", ".g", ".gc"}
LINE_BASE = 1_000_000_000  # as tests/support/rs274.rs: N<LINE_BASE + line> marks a main-program line
MOTIONS = re.compile(r"^\s*\d+ N\S*\s*(STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED|NURBS_FEED|STRAIGHT_PROBE|RIGID_TAP)\(", re.M)


def limits(mem_mb):
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (mem_mb << 20, mem_mb << 20))
    return apply


def is_subroutine_file(path):
    stem = os.path.splitext(os.path.basename(path))[0].lower()
    try:
        with open(path, "r", errors="replace") as fh:
            for line in fh:
                t = line.strip()
                if not t or t.startswith(";") or t.startswith("("):
                    continue
                return re.sub(r"\s", "", t.lower()).startswith(f"o<{stem}>sub")
    except OSError:
        return False
    return False


def programs(root, extensions):
    out = []
    for d, dirs, files in os.walk(root):
        dirs.sort()
        for f in sorted(files):
            p = os.path.join(d, f)
            if os.path.splitext(f)[1].lower() in extensions and not is_subroutine_file(p):
                out.append(p)
    return out


def number_lines(data):
    """The numbered copy: N<LINE_BASE + line> at the start of each line that can carry it."""
    out = []
    for i, raw in enumerate(data.split(b"\n")):
        body = raw.rstrip(b"\r")
        tail = raw[len(body):]
        stripped = body.lstrip(b" \t")
        lead = body[: len(body) - len(stripped)]
        if not stripped or stripped[:1] == b"%" or len(body) + 12 > 240:
            out.append(raw)
            continue
        slash = b""
        if stripped[:1] == b"/":
            slash, stripped = b"/", stripped[1:]
        m = re.match(rb"[nN][ \t]*\d+(\.\d*)?", stripped)
        if m:
            stripped = stripped[m.end():]
        out.append(lead + slash + b"N%d " % (LINE_BASE + i + 1) + stripped + tail)
    return b"\n".join(out)


def run_ours(binary, path, timeout, mem_mb):
    try:
        p = subprocess.run([binary, "replay", path], capture_output=True, timeout=timeout, preexec_fn=limits(mem_mb))
    except subprocess.TimeoutExpired:
        return {"status": "crashed", "why": f"more than {timeout} s", "motions": None, "unsupported": 0}
    out = p.stdout.decode("utf-8", "replace")
    err = p.stderr.decode("utf-8", "replace").strip()
    motions = None
    m = re.search(r"^moves\s+G00 (\d+), G01 (\d+), G02 (\d+), G03 (\d+), .*? curves (\d+)", out, re.M)
    if m:
        motions = sum(int(g) for g in m.groups())
    unsupported = len(re.findall(r"^UNSUPPORTED", out, re.M))
    if "panicked" in err or p.returncode not in (0, 1, 2):
        return {"status": "crashed", "why": f"exit {p.returncode}: {err.splitlines()[-1] if err else ''}", "motions": motions, "unsupported": unsupported}
    if p.returncode == 2:
        first = err.splitlines()[0] if err else ""
        # "interpolab: /path/to/file: line 6: …": the reason, without the path.
        first = first.removeprefix("interpolab: ").removeprefix(path + ": ")
        return {"status": "refused", "why": first, "motions": motions, "unsupported": unsupported}
    if p.returncode == 1:
        return {"status": "partial", "why": f"{unsupported} words left out", "motions": motions, "unsupported": unsupported}
    return {"status": "read", "why": "", "motions": motions, "unsupported": unsupported}


def run_rs274(path, timeout, mem_mb, table):
    tmp = tempfile.mkdtemp(prefix="corpus-rs274-")
    try:
        with open(path, "rb") as fh:
            data = fh.read()
        prog = os.path.join(tmp, os.path.basename(path))
        with open(prog, "wb") as fh:
            fh.write(number_lines(data))
        ini = os.path.join(tmp, "rs274.ini")
        with open(ini, "w") as fh:
            fh.write(f"[RS274NGC]\nSUBROUTINE_PATH = {os.path.dirname(os.path.abspath(path))}\n")
        cmd = ["rs274", "-t", table, "-v", os.path.join(tmp, "rs274.var"), "-i", ini, "-g", prog]
        env = dict(os.environ, HOME=tmp)
        try:
            p = subprocess.run(cmd, capture_output=True, timeout=timeout, preexec_fn=limits(mem_mb), cwd=tmp, env=env, stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            return {"status": "crashed", "line": None, "why": f"more than {timeout} s", "motions": None}
        out = p.stdout.decode("utf-8", "replace")
        motions = len(MOTIONS.findall(out))
        if p.returncode == 0:
            return {"status": "end", "line": None, "why": "", "motions": motions}
        lines = [l for l in p.stderr.decode("utf-8", "replace").splitlines() if l != "executing"]
        text = lines[-2] if len(lines) >= 2 else (lines[0] if lines else f"exit {p.returncode}")
        src = lines[-1] if len(lines) >= 2 else ""
        line = None
        m = re.match(r"\s*/?[nN](\d+)", src)
        if m and int(m.group(1)) > LINE_BASE:
            line = int(m.group(1)) - LINE_BASE
        elif src.strip():
            # A line left unnumbered (a `%` line): the first line of the program with that text.
            for i, raw in enumerate(data.split(b"\n")):
                if raw.rstrip(b"\r").decode("utf-8", "replace") == src:
                    line = i + 1
                    break
        if p.returncode < 0:
            return {"status": "crashed", "line": line, "why": f"signal {-p.returncode}", "motions": motions}
        return {"status": "error", "line": line, "why": text, "motions": motions}
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def cell(s, width=70):
    s = s.replace("|", "\\|")
    return s if len(s) <= width else s[: width - 1] + "…"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--binary", default=os.path.join(ROOT, "target/release/interpolab"))
    ap.add_argument("--json", help="write the per-program records here")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--ext", help="only these extensions, comma-separated (e.g. .ngc)")
    ap.add_argument("--timeout", type=float, default=30, help="seconds per run")
    ap.add_argument("--mem-mb", type=int, default=2048, help="address-space limit per run")
    a = ap.parse_args()
    if not os.path.isfile(a.binary):
        sys.exit(f"{a.binary} not found: build it (cargo build --release --no-default-features) or give --binary")
    if shutil.which("rs274") is None:
        sys.exit("rs274 not found: run scripts/setup.sh test (Debian package linuxcnc-uspace)")
    exts = {e.strip().lower() for e in a.ext.split(",")} if a.ext else EXTENSIONS
    files = programs(a.dir, exts)
    if not files:
        sys.exit(f"no program under {a.dir}")
    tmp = tempfile.mkdtemp(prefix="corpus-")
    table = os.path.join(tmp, "tools.tbl")
    with open(table, "w") as fh:
        fh.write("".join(f"T{i} P{i} D0 Z0 ;\n" for i in range(1, 1000)))

    def one(path):
        with open(path, "rb") as fh:
            n_lines = fh.read().count(b"\n")
        return {"file": os.path.relpath(path, a.dir), "lines": n_lines,
                "ours": run_ours(a.binary, path, a.timeout, a.mem_mb),
                "rs274": run_rs274(path, a.timeout, a.mem_mb, table)}

    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
            rows = list(ex.map(one, files))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    print("| program | lines | ours | our motions | rs274 | rs274 motions |")
    print("|---|---:|---|---:|---|---:|")
    for r in rows:
        o, l = r["ours"], r["rs274"]
        ours = o["status"] + (f": {o['why']}" if o["why"] else "")
        ref = "end" if l["status"] == "end" else f"{l['status']} line {l['line']}: {l['why']}"
        fmt = lambda n: "" if n is None else str(n)
        print(f"| {cell(r['file'], 60)} | {r['lines']} | {cell(ours)} | {fmt(o['motions'])} | {cell(ref)} | {fmt(l['motions'])} |")
    n = len(rows)
    count = lambda side, st: sum(1 for r in rows if r[side]["status"] == st)
    print()
    print(f"ours:  read {count('ours', 'read')} of {n}, read with words left out {count('ours', 'partial')}, "
          f"refused {count('ours', 'refused')}, crashed {count('ours', 'crashed')}")
    print(f"rs274: read to the end {count('rs274', 'end')} of {n}, stopped at an error {count('rs274', 'error')}, "
          f"crashed {count('rs274', 'crashed')}")
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
