#!/usr/bin/env python3
"""Print the module-level import graph of src/ and any cycle in it.

A "module" is the first path segment under src/ (src/chords/planar.rs and
src/chords/mod.rs are both `chords`; src/report.rs is `report`), except in the
directories of SPLIT, shelves of independent helpers whose files are modules of
their own: src/numerics/tolerance.rs is `numerics::tolerance` (geom uses it, and
numerics::measure uses geom: one directory, two floors), src/numerics/mod.rs is
`numerics`.  Edges come from `use crate::X...`, `crate::X::` paths in code
(`crate::numerics::Y::` for a split directory), and `super::` paths that climb
out of the top-level module (or name a sibling file of a split directory).
Usage:

    python3 scripts/modgraph.py [src_dir]

Exit status 1 when a cycle exists between top-level modules, or when an arrow
points up a floor: a module imports one on a higher floor of LAYERS (below), the
floors of src/lib.rs's layer list.  Modules of one floor may import each other (the
papers stand side by side and import another only where its method builds on it);
the cycle check keeps those arrows one-way.  Each offending import is named with the
first file and line where it occurs.  A module on no floor fails too (add it to
LAYERS), and so does an entry of UPWARD_EXCEPTIONS that is no longer needed.

    python3 scripts/modgraph.py --files [src_dir]

also looks for cycles between the files of one directory (src/geom/curve.rs using
`super::surface` while src/geom/surface.rs uses `super::curve`) and fails on those too: a
file's edges there are its `super::X` paths (from a file that is not mod.rs, outside its
inline `mod tests`) and `crate::a::b::X` paths naming a sibling X of the same directory.
"""
import os
import re
import sys

CRATE_RE = re.compile(r"\bcrate::([a-z_][a-z0-9_]*)(?:::([a-z_][a-z0-9_]*))?")
USE_GROUP_RE = re.compile(r"\buse\s+crate::\{([^;]*)\}", re.S)
SUPER_RE = re.compile(r"\b((?:super::)+)([a-z_][a-z0-9_]*)(?:::([a-z_][a-z0-9_]*))?")

# Directories under src/ whose files are graph nodes of their own (`numerics::tolerance`):
# shelves of helpers that stand on different floors (see src/numerics/mod.rs).
SPLIT = {"numerics"}


# The floors, bottom up, each a list of modules that may import only modules of its own or a
# lower floor. Keep in step with the layer list of src/lib.rs's `//!`. A file of a SPLIT
# directory not named here (numerics::format) is on the floor of its directory's entry
# (`numerics`).
LAYERS = [
    ("below geom", ["numerics::tolerance", "numerics::limits", "numerics::linalg"]),
    ("geometry", ["geom"]),
    ("numerics helpers", ["numerics"]),
    ("the papers", ["crease", "chords", "nurbs_path", "fiveaxis", "gcode", "fillet", "plan", "simulate"]),
    ("assembly and output", ["scene", "report"]),
    ("background jobs", ["jobs"]),
    ("the app", ["render", "app"]),
    ("crate root and binaries", ["lib", "main", "cli", "worker_main", "webgpu_main"]),
]

# Arrows up a floor tolerated for now: {(importer, imported): "why, and the issue to remove
# it"}. Empty since issue 25 (simulate imported scene for FinishJob, now in fillet).
UPWARD_EXCEPTIONS = {}


def floor_of(module):
    """Index of the module's floor in LAYERS, or None."""
    for i, (_, members) in enumerate(LAYERS):
        if module in members:
            return i
    if "::" in module:
        return floor_of(module.split("::")[0])
    return None


def upward_arrows(edges, sites):
    """Problems of the layering: arrows up a floor, modules on no floor, stale exceptions."""
    problems = []
    for m in sorted(edges):
        if floor_of(m) is None:
            problems.append(f"NO FLOOR: module {m} is on none of the floors; add it to LAYERS in scripts/modgraph.py")
    used = set()
    for m in sorted(edges):
        fm = floor_of(m)
        for t in sorted(edges[m]):
            ft = floor_of(t)
            if fm is None or ft is None or ft <= fm:
                continue
            if (m, t) in UPWARD_EXCEPTIONS:
                used.add((m, t))
                continue
            where = ", ".join(f"{f}:{line}" for f, line in sorted(sites.get((m, t), []))[:3])
            problems.append(
                f"ARROW UP A FLOOR: {m} ({LAYERS[fm][0]}) imports {t} ({LAYERS[ft][0]})"
                + (f" at {where}" if where else "")
                + "; move what it needs down a floor, or the importer up"
            )
    for e in sorted(set(UPWARD_EXCEPTIONS) - used):
        problems.append(f"STALE EXCEPTION: {e[0]} -> {e[1]} no longer points up a floor; remove it from UPWARD_EXCEPTIONS")
    return problems


def top_module(rel):
    parts = rel.split(os.sep)
    if len(parts) == 1:
        return parts[0][:-3]  # foo.rs -> foo (lib, main included)
    if parts[0] in SPLIT and parts[1] != "mod.rs":
        return parts[0] + "::" + (parts[1][:-3] if parts[1].endswith(".rs") else parts[1])
    return parts[0]


def node(first, second):
    """The graph node a path `crate::first::second` names."""
    if first in SPLIT and second:
        return first + "::" + second
    return first


def depth_in_module(rel):
    """Segments of the file's module path: a.rs and a/mod.rs are 1, a/b.rs is 2.

    `super::` hops fewer than this stay inside the top-level module; with as
    many hops the path names a top-level module (inline `mod tests` blocks
    add one level, so a `super::` chain there is read one hop short, which
    only ever hides an edge into the module itself).
    """
    parts = rel.split(os.sep)
    d = len(parts)
    if parts[-1] == "mod.rs":
        d -= 1
    return d


def strip_comments(text):
    """The text without comments; line breaks kept, so lines keep their numbers."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def strongly_connected(edges):
    """Strongly connected components with more than one member (the cycles)."""
    index, low, stack, on, sccs = {}, {}, [], set(), []
    counter = [0]

    def strong(v):
        work = [(v, iter(sorted(edges.get(v, ()))))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        while work:
            node, it = work[-1]
            advanced = False
            for w in it:
                if w not in edges:
                    continue
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                    advanced = True
                    break
                if w in on:
                    low[node] = min(low[node], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == node:
                        break
                if len(comp) > 1:
                    sccs.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            strong(v)
    for v in sorted(edges):
        if v not in index:
            strong(v)
    return sccs


def file_edges(src):
    """Edges between sibling files of each directory: {dir: {file: {sibling, ...}}}."""
    out = {}
    for root, dirs, files in os.walk(src):
        rel_dir = os.path.relpath(root, src)
        if rel_dir == ".":
            continue
        siblings = {f[:-3] for f in files if f.endswith(".rs") and f != "mod.rs"}
        siblings |= {d for d in dirs if os.path.exists(os.path.join(root, d, "mod.rs"))}
        crate_path = "crate::" + rel_dir.replace(os.sep, "::") + "::"
        sib_re = re.compile(r"(?<![a-z_:])(?:super::|" + re.escape(crate_path) + r")([a-z_][a-z0-9_]*)")
        group_re = re.compile(r"\buse\s+super::\{([^;]*)\}", re.S)
        edges = out.setdefault(rel_dir, {})
        for f in files:
            if not f.endswith(".rs") or f == "mod.rs":
                continue
            me = f[:-3]
            with open(os.path.join(root, f), encoding="utf-8") as fh:
                text = strip_comments(fh.read())
            # inline `mod tests` blocks reach the file itself through super::; ignore them
            text = re.split(r"#\[cfg\(test\)\]\s*mod\s+tests", text)[0]
            targets = set(sib_re.findall(text))
            for group in group_re.findall(text):
                for item in re.split(r",(?![^{]*\})", group):
                    m = re.match(r"\s*([a-z_][a-z0-9_]*)", item)
                    if m:
                        targets.add(m.group(1))
            edges[me] = {t for t in targets if t in siblings and t != me}
        for d in dirs:
            if os.path.exists(os.path.join(root, d, "mod.rs")):
                edges.setdefault(d, set())
    return out


def main():
    args = [a for a in sys.argv[1:] if a != "--files"]
    check_files = "--files" in sys.argv[1:]
    src = args[0] if args else "src"
    edges = {}
    sites = {}  # (module, module) -> [(file, line), ...] of the imports
    known = {
        (e[:-3] if e.endswith(".rs") else e)
        for e in os.listdir(src)
        if e.endswith(".rs") or os.path.isdir(os.path.join(src, e))
    }
    for d in SPLIT:
        if os.path.isdir(os.path.join(src, d)):
            known |= {top_module(os.path.join(d, e)) for e in os.listdir(os.path.join(src, d)) if e != "mod.rs"}
    for root, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            path = os.path.join(root, f)
            rel = os.path.relpath(path, src)
            me = top_module(rel)
            with open(path, encoding="utf-8") as fh:
                text = strip_comments(fh.read())
            found = []  # (target, offset in text)
            for m in CRATE_RE.finditer(text):
                found.append((node(m.group(1), m.group(2)), m.start()))
            for g in USE_GROUP_RE.finditer(text):
                for item in re.split(r",(?![^{]*\})", g.group(1)):
                    item = item.strip()
                    m = re.match(r"([a-z_][a-z0-9_]*)(?:::([a-z_][a-z0-9_]*))?", item)
                    if m:
                        found.append((node(m.group(1), m.group(2)), g.start()))
            depth = depth_in_module(rel)
            split_file = "::" in me
            for m in SUPER_RE.finditer(text):
                hops = m.group(1).count("super::")
                if hops == depth:
                    found.append((node(m.group(2), m.group(3)), m.start()))
                elif split_file and hops == depth - 1:
                    found.append((node(me.split("::")[0], m.group(2)), m.start()))  # a sibling file of the shelf
            edges.setdefault(me, set())
            for t, at in found:
                if t != me and t in known:
                    edges[me].add(t)
                    sites.setdefault((me, t), []).append((os.path.join(src, rel), text.count("\n", 0, at) + 1))
    for m in sorted(edges):
        print(f"{m} -> {', '.join(sorted(edges[m])) or '(nothing)'}")
    sccs = strongly_connected(edges)
    file_cycles = []
    for d, edges_d in sorted(file_edges(src).items() if check_files else []):
        for c in strongly_connected(edges_d):
            file_cycles.append(d + "/{" + ", ".join(f + ".rs" for f in c) + "}")
    layering = upward_arrows(edges, sites)
    if sccs or file_cycles or layering:
        for c in sccs:
            print("CYCLE among: " + ", ".join(c))
        for c in file_cycles:
            print("FILE CYCLE among: " + c)
        for p in layering:
            print(p)
        return 1
    print("no cycle" + (" (between modules, nor between the files of a directory)" if check_files else ""))
    print(f"no arrow up a floor ({len(LAYERS)} floors, {len(UPWARD_EXCEPTIONS)} known exceptions)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
