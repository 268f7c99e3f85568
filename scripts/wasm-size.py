#!/usr/bin/env python3
"""Where a .wasm file's bytes are: the size of each section, and the code section's bytes by
crate (the first path segment of each function's name) and by function.

It needs the name section, so run it on wasm-bindgen's output made with --keep-debug, before
wasm-opt (which drops the names):

    cargo build --profile wasm-release --target wasm32-unknown-unknown --lib
    wasm-bindgen --target web --no-typescript --keep-debug --out-dir /tmp/pkg \\
      target/wasm32-unknown-unknown/wasm-release/paretomesh.wasm
    python3 scripts/wasm-size.py /tmp/pkg/paretomesh_bg.wasm [how many functions]

Generic functions are named after the crate that defines them (core, alloc, hashbrown), not the
one that instantiates them.
"""
import collections
import re
import sys

SECTIONS = {1: 'type', 2: 'import', 3: 'function', 4: 'table', 5: 'memory', 6: 'global',
            7: 'export', 8: 'start', 9: 'elem', 10: 'code', 11: 'data', 12: 'datacount'}


def leb(b, i):
    result = shift = 0
    while True:
        x = b[i]
        i += 1
        result |= (x & 0x7F) << shift
        shift += 7
        if x < 0x80:
            return result, i


def skip_limits(b, q):
    flags, q = leb(b, q)
    _, q = leb(b, q)
    if flags & 1:
        _, q = leb(b, q)
    return q


def main(path, top):
    b = open(path, 'rb').read()
    imported = 0
    code = []
    names = {}
    sizes = collections.Counter()
    i = 8
    while i < len(b):
        sid = b[i]
        n, i = leb(b, i + 1)
        end = i + n
        if sid == 0:
            length, j = leb(b, i)
            name = b[j:j + length].decode(errors='replace')
            sizes['custom:' + name] += n
            if name == 'name':
                k = j + length
                while k < end:
                    sub = b[k]
                    sub_len, k = leb(b, k + 1)
                    if sub == 1:
                        count, q = leb(b, k)
                        for _ in range(count):
                            index, q = leb(b, q)
                            length, q = leb(b, q)
                            names[index] = b[q:q + length].decode(errors='replace')
                            q += length
                    k += sub_len
        else:
            sizes[SECTIONS.get(sid, str(sid))] += n
        if sid == 2:
            count, q = leb(b, i)
            for _ in range(count):
                for _ in range(2):
                    length, q = leb(b, q)
                    q += length
                kind = b[q]
                q += 1
                if kind == 0:
                    _, q = leb(b, q)
                    imported += 1
                elif kind == 1:
                    q = skip_limits(b, q + 1)
                elif kind == 2:
                    q = skip_limits(b, q)
                elif kind == 3:
                    q += 2
                else:
                    _, q = leb(b, q + 1)
        if sid == 10:
            count, q = leb(b, i)
            for k in range(count):
                body, start = leb(b, q)
                code.append((imported + k, body + start - q))
                q = start + body
        i = end
    print('sections:')
    for name, size in sizes.most_common():
        print(f'  {size:>9}  {name}')
    by_crate = collections.Counter()
    functions = []
    for index, size in code:
        name = names.get(index, f'func[{index}]')
        functions.append((size, name))
        match = re.match(r'[<&\s]*(?:mut |dyn )?([A-Za-z_][A-Za-z0-9_]*)', name)
        by_crate[match.group(1) if match else '?'] += size
    print(f'code by crate ({sum(s for s, _ in functions)} bytes):')
    for crate, size in by_crate.most_common(30):
        print(f'  {size:>9}  {crate}')
    print('largest functions:')
    for size, name in sorted(functions, reverse=True)[:top]:
        print(f'  {size:>9}  {name[:160]}')


if __name__ == '__main__':
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 30)
