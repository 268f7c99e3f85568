#!/usr/bin/env python3
"""Lists the import circles between the files of src/: every crate::, super:: and self:: path in
code (comments skipped) is an arrow from its file to the file it names, and each strongly
connected group of two or more files is printed with its arrows. Then the arrows between the
top-level modules. `python3 scripts/import-cycles.py` (exit status 1 when a circle is found).
"""
import os, re, sys
root = sys.argv[1] if len(sys.argv) > 1 else 'src'
mods = {}
for dp, _, fs in os.walk(root):
    for f in fs:
        if f.endswith('.rs'):
            p = os.path.join(dp, f)
            rel = os.path.relpath(p, root)[:-3].split(os.sep)
            if rel[-1] == 'mod' or rel == ['lib']:
                rel = rel[:-1]
            mods[tuple(rel)] = p
def resolve(path):
    # longest prefix that is a module file
    for k in range(len(path), 0, -1):
        if tuple(path[:k]) in mods:
            return tuple(path[:k])
    return None
edges = {m: set() for m in mods}
for m, p in mods.items():
    me = list(m)
    code = '\n'.join(l.split('//')[0] for l in open(p, encoding='utf8'))
    for mt in re.finditer(r'\b(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)+)', code):
        head, rest = mt.group(1), mt.group(2).split('::')[1:]
        if head == 'crate':
            base = []
        elif head == 'super':
            base = me[:-1]
            while rest and rest[0] == 'super':
                base = base[:-1]
                rest = rest[1:]
        else:
            base = me
        t = resolve(base + rest)
        if t and t != m and not (t == tuple(m[:len(t)])):
            edges[m].add(t)
# also `use super::{a, b}` groups
for m, p in mods.items():
    me = list(m)
    code = '\n'.join(l.split('//')[0] for l in open(p, encoding='utf8'))
    for mt in re.finditer(r'use (crate|super)((?:::[a-z_][a-z0-9_]*)*)::\{([^}]*)\}', code):
        base = [] if mt.group(1) == 'crate' else me[:-1]
        base = base + [x for x in mt.group(2).split('::') if x]
        for item in mt.group(3).split(','):
            item = item.strip().split('::')[0].split(' ')[0]
            if item and item != 'self':
                t = resolve(base + [item])
                if t and t != m and not (t == tuple(m[:len(t)])):
                    edges[m].add(t)
# strongly connected components (Tarjan)
idx, low, stack, on, out, n = {}, {}, [], set(), [], [0]
sys.setrecursionlimit(10000)
def sc(v):
    idx[v] = low[v] = n[0]
    n[0] += 1
    stack.append(v)
    on.add(v)
    for w in edges[v]:
        if w not in idx:
            sc(w)
            low[v] = min(low[v], low[w])
        elif w in on:
            low[v] = min(low[v], idx[w])
    if low[v] == idx[v]:
        comp = []
        while True:
            w = stack.pop()
            on.discard(w)
            comp.append(w)
            if w == v:
                break
        if len(comp) > 1:
            out.append(comp)
for v in mods:
    if v not in idx:
        sc(v)
for c in out:
    names = sorted('/'.join(x) for x in c)
    print(f'cycle of {len(c)}:', ', '.join(names))
    for a in c:
        for b in edges[a]:
            if b in c:
                print('   ', '/'.join(a), '->', '/'.join(b))
# top-level modules
top = {}
for a, bs in edges.items():
    for b in bs:
        if a and b and a[0] != b[0]:
            top.setdefault(a[0], set()).add(b[0])
for a in sorted(top):
    print('top', a, '->', ' '.join(sorted(top[a])))
sys.exit(1 if out else 0)
