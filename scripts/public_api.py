#!/usr/bin/env python3
"""The library's public API as sorted paths, read from rustdoc's HTML (stable Rust).

Usage: public_api.py DOC_DIR, where DOC_DIR is target/doc/paretomesh after
`cargo doc --no-deps --lib`. Prints one line per public module, item, enum variant, field,
inherent method and associated item, trait method, and re-export of an item documented
elsewhere: `kind path`. Trait implementations
(derived or written) are left out: they change with derives, not with what users call.
"""
import html
import os
import re
import sys

PAGE = re.compile(r'^(struct|enum|trait|fn|type|constant|static|macro|union|traitalias)\.(\w+)\.html$')
KINDS = {'constant': 'const'}


def members(text, kind):
    """The page's own members: fields, variants, inherent and trait-declared methods."""
    out = []
    for m in re.finditer(r'id="(structfield|variant)\.(\w+)"', text):
        out.append((m.group(1).replace('structfield', 'field'), m.group(2)))
    for m in re.finditer(r'id="variant\.(\w+)\.field\.(\w+)"', text):
        out.append(('field', f'{m.group(1)}.{m.group(2)}'))
    # Inherent impls sit between id="implementations-list" and the trait impls.
    start = text.find('id="implementations-list"')
    if start >= 0:
        ends = [text.find(marker, start) for marker in (
            'id="trait-implementations', 'id="synthetic-implementations',
            'id="blanket-implementations', 'id="deref-methods')]
        ends = [e for e in ends if e >= 0]
        section = text[start:min(ends) if ends else len(text)]
        for m in re.finditer(r'id="(method|associatedconstant|associatedtype)\.(\w+)"', section):
            out.append((m.group(1).replace('associated', 'assoc_'), m.group(2)))
    if kind == 'trait':
        for m in re.finditer(r'id="(tymethod|method|associatedtype|associatedconstant)\.(\w+)"', text):
            out.append(('trait_' + m.group(1).replace('tymethod', 'method')
                        .replace('associated', 'assoc_'), m.group(2)))
    return sorted(set(out))


def main(doc):
    lines = set()
    for directory, _, files in os.walk(doc):
        module = os.path.relpath(directory, os.path.dirname(doc)).replace(os.sep, '::')
        if 'index.html' in files:
            lines.add(f'mod {module}')
            # Re-exports of items documented elsewhere (a public module's item, re-exported).
            index = open(os.path.join(directory, 'index.html'), encoding='utf-8').read()
            for m in re.finditer(r'id="reexport\.(\w+)"', index):
                lines.add(f'use {module}::{m.group(1)}')
        for name in files:
            m = PAGE.match(name)
            if not m:
                continue
            text = open(os.path.join(directory, name), encoding='utf-8').read()
            # Re-export stubs only redirect to the item's page.
            if '<title>Redirection</title>' in text or 'http-equiv="refresh"' in text:
                continue
            kind, item = KINDS.get(m.group(1), m.group(1)), m.group(2)
            path = f'{module}::{item}'
            lines.add(f'{kind} {path}')
            for member_kind, member in members(text, m.group(1)):
                lines.add(f'{member_kind} {path}::{html.unescape(member)}')
    print('\n'.join(sorted(lines)))


if __name__ == '__main__':
    main(sys.argv[1])
