#!/usr/bin/env python3
"""Lists the import circles between the files of src/: every crate::, super:: and self:: path in
code (comments skipped) is an arrow from its file to the file it names, and each strongly
connected group of two or more files is printed with its arrows. Then the arrows between the
top-level modules, and checks them against ARCHITECTURE.md's module table.

The table (between the `module-table` markers) has a row per top-level module, `main.rs` and
`cli` included (the binary reaches the library by `paretomesh::` paths), and lists in its second
column the modules it uses directly, left out those a longer path implies (the transitive
reduction), from code outside tests (`#[cfg(test)]` items, tests.rs files and tests/ folders).

    python3 scripts/import-cycles.py            # exit status 1 on a circle or a table that lies
    python3 scripts/import-cycles.py --write    # rewrite the table's arrows (rows kept in order)
"""
import os, re, sys
args = [a for a in sys.argv[1:] if not a.startswith('--')]
write = '--write' in sys.argv[1:]
root = args[0] if args else 'src'
doc = os.path.join(os.path.dirname(os.path.abspath(root)), 'ARCHITECTURE.md')
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

def without_tests(code):
    """`code` without the items under `#[cfg(test)]` (or `#[cfg(all(test, ...))]`)."""
    out, at = [], 0
    for mt in re.finditer(r'#\[cfg\((?:all\()?test\b[^\]]*\]', code):
        if mt.start() < at:
            continue
        out.append(code[at:mt.start()])
        i = mt.end()
        semi, brace = code.find(';', i), code.find('{', i)
        if semi != -1 and (brace == -1 or semi < brace):
            at = semi + 1
            continue
        depth = 0
        for j in range(brace, len(code)):
            depth += {'{': 1, '}': -1}.get(code[j], 0)
            if depth == 0:
                break
        at = j + 1
    return ''.join(out) + code[at:]


def module_arrows():
    """Top-level module -> the top-level modules its code outside tests names."""
    test_only = set()
    for m, p in mods.items():
        code = open(p, encoding='utf8').read()
        for mt in re.finditer(r'#\[cfg\((?:all\()?test\b[^\]]*\]\s*(?:pub(?:\([a-z]+\))?\s+)?mod (\w+);', code):
            test_only.add(m + (mt.group(1),))
    arrows = {}
    for m, p in mods.items():
        if not m or 'tests' in m or any(m[:k] in test_only for k in range(1, len(m) + 1)):
            continue
        code = '\n'.join(l.split('//')[0] for l in open(p, encoding='utf8'))
        code = without_tests(code)
        top_of = m[0]
        arrows.setdefault(top_of, set())
        names = set()
        if top_of in ('main', 'cli'):
            names |= set(re.findall(r'\bparetomesh::([a-z_][a-z0-9_]*)', code))
            names |= {'cli'} if top_of == 'main' and re.search(r'\bmod cli\b', code) else set()
        for mt in re.finditer(r'\bcrate((?:::[A-Za-z_][A-Za-z0-9_]*)+)', code):
            names.add(mt.group(1).split('::')[1])
        for mt in re.finditer(r'use crate::\{([^}]*)\}', code):
            names |= {x.strip().split('::')[0] for x in mt.group(1).split(',') if x.strip()}
        arrows[top_of] |= {n for n in names if (n,) in mods and n != top_of}
    return arrows


def reduction(arrows):
    """The arrows no longer path implies (the graph is acyclic: a circle was reported above)."""
    def reach(a, seen):
        for b in arrows.get(a, ()):
            if b not in seen:
                seen.add(b)
                reach(b, seen)
        return seen
    return {a: {b for b in bs if not any(b in reach(c, set()) for c in bs if c != b)}
            for a, bs in arrows.items()}


def table_agrees():
    """Compares ARCHITECTURE.md's module table with the code; rewrites it with --write."""
    text = open(doc, encoding='utf8').read()
    begin, end = '<!-- module-table:begin -->', '<!-- module-table:end -->'
    if begin not in text or end not in text:
        print(f'{doc}: no {begin} ... {end} table')
        return False
    head, rest = text.split(begin, 1)
    table, tail = rest.split(end, 1)
    want = reduction(module_arrows())
    name = lambda cell: cell.strip().strip('`').removesuffix('.rs').removesuffix('/')
    rows, lines = {}, table.strip('\n').split('\n')
    for line in lines[2:]:
        cells = [c.strip() for c in line.strip().strip('|').split('|')]
        if len(cells) != 3:
            print(f'ARCHITECTURE.md: the module table has a row that is not 3 cells: {line!r}')
            return False
        uses = set() if cells[1] in ('', '—') else {name(c) for c in cells[1].split(',')}
        rows[name(cells[0])] = (cells, uses)
    if write:
        out = lines[:2]
        for m, (cells, _) in rows.items():
            if m in want:
                cells[1] = ', '.join(f'`{b}`' for b in sorted(want[m])) or '—'
                out.append('| ' + ' | '.join(cells) + ' |')
        out += [f'| `{m}` | ' + (', '.join(f'`{b}`' for b in sorted(want[m])) or '—') + ' | ? |'
                for m in sorted(want) if m not in rows]
        open(doc, 'w', encoding='utf8').write(head + begin + '\n' + '\n'.join(out) + '\n' + end + tail)
        print(f'wrote the module table of {doc}')
        return True
    ok = True
    for m in sorted(set(want) | set(rows)):
        if m not in rows:
            print(f'ARCHITECTURE.md: module {m} has no row (it uses {sorted(want[m])})')
        elif m not in want:
            print(f'ARCHITECTURE.md: module {m} is in the table but not in src/')
        elif rows[m][1] != want[m]:
            print(f'ARCHITECTURE.md: {m} uses {sorted(want[m])} (arrows a longer path implies '
                  f'left out), the table says {sorted(rows[m][1])}')
        else:
            continue
        ok = False
    order = list(rows)
    for m in order:
        for b in sorted(rows[m][1] & set(order)):
            if order.index(b) < order.index(m):
                print(f'ARCHITECTURE.md: {m} uses {b}, which its table lists above it')
                ok = False
    if not ok:
        print('fix the table, or `python3 scripts/import-cycles.py --write` and check its words')
    return ok


# top-level modules, outside tests
top = module_arrows()
for a in sorted(top):
    print('top', a, '->', ' '.join(sorted(top[a])))
sys.exit(1 if out or not table_agrees() else 0)
