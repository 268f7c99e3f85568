// Seeded terrains for the browser tests and benches, from the project's one terrain generator
// (scripts/terrain.py, numpy), with the project's Python (.venv-python, made by
// scripts/setup.sh) or else python3.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');

// `scripts/terrain.py FAMILY --size SIZE --seed SEED` as a raw f32 grid and its sidecar, named
// NAME.f32 and NAME.json, ready for `dropFiles`; `z` is the grid's heights (row-major).
export function terrainGrid(family, size, { seed = 1, name = `${family}_${size}` } = {}) {
  const venv = path.join(root, '.venv-python/bin/python');
  const python = existsSync(venv) ? venv : 'python3';
  const dir = mkdtempSync(path.join(tmpdir(), 'pm-terrain-'));
  try {
    const out = path.join(dir, `${name}.f32`);
    execFileSync(python, [path.join(root, 'scripts/terrain.py'), family, '--size', String(size), '--seed', String(seed), '--out', out],
      { stdio: ['ignore', 'ignore', 'inherit'] });
    const bytes = readFileSync(out);
    const files = [{ name: `${name}.f32`, bytes }, { name: `${name}.json`, bytes: readFileSync(out.replace(/\.f32$/, '.json')) }];
    const z = new Float32Array(bytes.buffer, bytes.byteOffset, bytes.length / 4);
    return { files, z };
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}
