#!/usr/bin/env python3
"""Where a wasm module's code is: function body sizes from the code section, named by the
name section (a module before wasm-opt, e.g. target/wasm32-unknown-unknown/web-release/
interpolab.wasm), summed by crate (and by module for interpolab; a trait impl counts for the
crate of its type). Usage:
    python3 scripts/wasm-sizes.py MODULE.wasm
"""
import sys, re, collections
data = open(sys.argv[1], 'rb').read()
def leb(b, i):
    r = s = 0
    while True:
        x = b[i]; i += 1
        r |= (x & 0x7f) << s; s += 7
        if x < 0x80: return r, i
assert data[:4] == b'\0asm'
i = 8; sections = []
while i < len(data):
    sid = data[i]; i += 1
    size, i = leb(data, i)
    sections.append((sid, i, size)); i += size
nimports = 0
for sid, off, size in sections:
    if sid == 2:
        n, j = leb(data, off)
        for _ in range(n):
            l, j = leb(data, j); j += l
            l, j = leb(data, j); j += l
            kind = data[j]; j += 1
            if kind == 0: _, j = leb(data, j); nimports += 1
            elif kind == 1: j += 1; fl, j = leb(data, j); _, j = leb(data, j); 
            elif kind == 2:
                fl, j = leb(data, j); _, j = leb(data, j)
                if fl & 1: _, j = leb(data, j)
            elif kind == 3: j += 2
sizes = {}
for sid, off, size in sections:
    if sid == 10:
        n, j = leb(data, off)
        for k in range(n):
            l, j2 = leb(data, j)
            sizes[nimports + k] = l + (j2 - j); j = j2 + l
names = {}
for sid, off, size in sections:
    if sid == 0:
        l, j = leb(data, off); nm = data[j:j+l]; j += l
        if nm != b'name': continue
        end = off + size
        while j < end:
            sub = data[j]; j += 1
            ss, j = leb(data, j)
            if sub == 1:
                n, k = leb(data, j)
                for _ in range(n):
                    idx, k = leb(data, k); l, k = leb(data, k); names[idx] = data[k:k+l].decode('utf8', 'replace'); k += l
            j += ss
def crate(n):
    if n.startswith('_R'):
        m = re.search(r'Cs[0-9a-zA-Z]*_(\d+)([A-Za-z_][A-Za-z0-9_]*)', n)
        if m:
            L = int(m.group(1)); c = m.group(2)[:L]
            if c == 'interpolab':
                rest = m.group(2)[L:]
                m2 = re.match(r'(\d+)([a-z_][a-z0-9_]*)', rest)
                if m2: return 'interpolab::' + m2.group(2)[:int(m2.group(1))]
            return c
    # A trait impl, `<Type as Trait>::method`: the crate (and module) of the type.
    m = re.match(r'_ZN\d+_\$LT\$([A-Za-z_][A-Za-z0-9_]*)\.\.([A-Za-z_][A-Za-z0-9_]*)', n)
    if m:
        return 'interpolab::' + m.group(2) if m.group(1) == 'interpolab' else m.group(1)
    m = re.match(r'_ZN(\d+)(\w+)', n)
    if m:
        L = int(m.group(1)); c = m.group(2)[:L]
        if c == 'interpolab':
            rest = m.group(2)[L:]
            m2 = re.match(r'(\d+)', rest)
            if m2:
                L2 = int(m2.group(1)); mod = rest[len(m2.group(1)):len(m2.group(1))+L2]
                return 'interpolab::' + mod
        return c
    m = re.search(r'<(\w+)::', n)
    if m: return m.group(1) + ' (impl)'
    return n.split('::')[0][:40]
agg = collections.Counter()
for idx, sz in sizes.items():
    agg[crate(names.get(idx, '?'))] += sz
tot = sum(sizes.values())
print('code bytes', tot, 'named', len(names))
for c, s in agg.most_common(30):
    print(f'{s:9d} {100 * s / tot:5.1f}% {c}')
