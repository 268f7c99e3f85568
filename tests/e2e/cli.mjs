// The CLI's debug build, the one `cargo test` builds, for the end-to-end tests that compare the
// browser's fronts with the CLI's.
import { readFileSync, existsSync, mkdtempSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';
import { root } from './harness.mjs';

export const cli = path.join(root, 'target/debug/paretomesh');
assert.ok(existsSync(cli), 'build the CLI first: cargo build --bin paretomesh');

// The CLI's front for `paretomesh run ARGS`, as [T, E_sum] pairs.
export function cliFront(args) {
  const out = path.join(mkdtempSync(path.join(tmpdir(), 'pm-')), 'front.json');
  execFileSync(cli, ['run', ...args, '--out', out], { stdio: ['ignore', 'ignore', 'inherit'] });
  return JSON.parse(readFileSync(out, 'utf8')).front.map((m) => [m.T, m.E_sum]);
}
