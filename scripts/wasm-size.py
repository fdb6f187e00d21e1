#!/usr/bin/env python3
"""Where the bytes of a wasm module are: its sections, and its code by crate (from the `name`
section, so use the module cargo builds, before wasm-opt strips the names:
target/wasm32-unknown-unknown/web-release/interpolab.wasm after `trunk build --release`).

    scripts/wasm-size.py [WASM] [TOP]
"""
import re
import sys
from collections import Counter


def leb(data, pos):
    result, shift = 0, 0
    while True:
        b = data[pos]
        pos += 1
        result |= (b & 0x7F) << shift
        shift += 7
        if b < 0x80:
            return result, pos


def crate_of(name):
    """The crate a (legacy- or v0-mangled, or demangled) Rust symbol belongs to."""
    m = re.match(r"_ZN(\d+)", name)
    if m:
        n = int(m.group(1))
        start = m.end()
        seg = name[start:start + n]
        if seg.startswith("_$LT$"):
            # <T as Trait>::f: the implementing type's crate.
            inner = re.match(r"_\$LT\$([A-Za-z0-9_]+)", seg)
            return inner.group(1) if inner else "generic"
        return seg
    m = re.match(r"_R[A-Za-z]*?C[s0-9_]*?(\d+)([A-Za-z_][A-Za-z0-9_]*)", name)
    if m:
        return m.group(2)[: int(m.group(1))]
    m = re.match(r"<?([A-Za-z_][A-Za-z0-9_]*)::", name)
    if m:
        return m.group(1)
    return "(no crate: " + ("wasm-bindgen glue" if "wbg" in name or "wasm_bindgen" in name else "other") + ")"


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "target/wasm32-unknown-unknown/web-release/interpolab.wasm"
    top = int(sys.argv[2]) if len(sys.argv) > 2 else 25
    data = open(path, "rb").read()
    pos = 8
    sections = []
    imported_funcs = 0
    bodies = []
    names = {}
    while pos < len(data):
        sid = data[pos]
        size, p = leb(data, pos + 1)
        body = data[p:p + size]
        label = {0: "custom", 1: "type", 2: "import", 3: "function", 5: "memory", 6: "global", 7: "export",
                 9: "element", 10: "code", 11: "data"}.get(sid, str(sid))
        if sid == 0:
            n, q = leb(body, 0)
            label = "custom:" + body[q:q + n].decode(errors="replace")
            if label == "custom:name":
                r = q + n
                while r < len(body):
                    sub = body[r]
                    sub_size, r2 = leb(body, r + 1)
                    if sub == 1:
                        count, t = leb(body, r2)
                        for _ in range(count):
                            idx, t = leb(body, t)
                            ln, t = leb(body, t)
                            names[idx] = body[t:t + ln].decode(errors="replace")
                            t += ln
                    r = r2 + sub_size
        elif sid == 2:
            count, t = leb(body, 0)
            for _ in range(count):
                for _ in range(2):
                    ln, t = leb(body, t)
                    t += ln
                kind = body[t]
                t += 1
                if kind == 0:
                    _, t = leb(body, t)
                    imported_funcs += 1
                elif kind == 1:
                    t += 1
                    flags = body[t]
                    _, t = leb(body, t + 1)
                    if flags & 1:
                        _, t = leb(body, t)
                elif kind == 2:
                    flags = body[t]
                    _, t = leb(body, t + 1)
                    if flags & 1:
                        _, t = leb(body, t)
                elif kind == 3:
                    t += 2
        elif sid == 10:
            count, t = leb(body, 0)
            for _ in range(count):
                sz, t2 = leb(body, t)
                bodies.append(t2 - t + sz)
                t = t2 + sz
        sections.append((label, size))
        pos = p + size
    print(f"{path}: {len(data)} bytes")
    for label, size in sorted(sections, key=lambda s: -s[1]):
        print(f"  {label:<28} {size:>10}")
    by_crate = Counter()
    for i, sz in enumerate(bodies):
        by_crate[crate_of(names.get(imported_funcs + i, "?"))] += sz
    print(f"code by crate ({len(bodies)} functions{'' if names else ', no name section'}):")
    for crate, sz in by_crate.most_common(top):
        print(f"  {crate:<28} {sz:>10}")


if __name__ == "__main__":
    main()
