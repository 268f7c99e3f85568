// The 3D Tiles pyramid with real readers. The CLI's debug build (target/debug/paretomesh, built
// by `cargo test`) runs greedy insertion on a UTM GeoTIFF and writes a 4-level pyramid to
// target/e2e/pyramid; the Khronos glTF validator checks every glb (no errors); then CesiumJS
// (npm `cesium`, served from node_modules/cesium/Build/Cesium, offline: no Ion token, no base
// layer, no terrain) shows it in headless Chromium: with a small screen-space error every tile
// of the finest level loads, with a huge one the root alone does, no tile fails, no page error,
// and no request leaves this machine. A screenshot goes to target/e2e/.
import { chromium } from 'playwright-core';
import { spawn, execFileSync } from 'node:child_process';
import { createServer } from 'node:net';
import { mkdirSync, rmSync, readFileSync, existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';
import assert from 'node:assert/strict';
import validator from 'gltf-validator';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const cli = path.join(process.env.CARGO_TARGET_DIR ?? path.join(root, 'target'), 'debug/paretomesh');
assert.ok(existsSync(cli), 'build the CLI first: cargo build');
const out = path.join(root, 'target/e2e/pyramid');
rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
const LEVELS = 4;

// 1. A front and its pyramid.
const front = path.join(out, 'front.json');
execFileSync(cli, ['run', path.join(root, 'tests/data/jacksboro_65x65_utm16n.tif'), '--algo', 'greedy', '--out', front], { stdio: 'ignore' });
execFileSync(cli, ['tiles', front, '--out', path.join(out, 'tiles'), '--levels', String(LEVELS)], { stdio: 'inherit' });
const tileset = JSON.parse(readFileSync(path.join(out, 'tiles/tileset.json'), 'utf8'));
const tiles = [];
(function walk(t, depth) { tiles.push({ uri: t.content.uri, depth }); (t.children ?? []).forEach((c) => walk(c, depth + 1)); })(tileset.root, 0);
assert.equal(tiles.length, (4 ** LEVELS - 1) / 3);

// 2. Every glb through the Khronos validator.
let errors = 0;
for (const { uri } of tiles) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(path.join(out, 'tiles', uri))));
  if (report.issues.numErrors > 0) console.log(uri, JSON.stringify(report.issues.messages.slice(0, 3)));
  errors += report.issues.numErrors;
}
assert.equal(errors, 0, 'gltf-validator finds no error in any tile');
console.log(`gltf-validator: ${tiles.length} tiles, 0 errors`);

// 3. CesiumJS in headless Chromium.
function freePort() {
  return new Promise((resolve, reject) => {
    const s = createServer();
    s.once('error', reject);
    s.listen(0, '127.0.0.1', () => { const { port } = s.address(); s.close(() => resolve(port)); });
  });
}
const port = await freePort();
const server = spawn('python3', ['-m', 'http.server', '--bind', '127.0.0.1', String(port)], { cwd: root, stdio: 'ignore' });
const base = `http://127.0.0.1:${port}/`;
let browser;
try {
  for (let i = 0; i < 100; i++) {
    try { if ((await fetch(base)).ok) break; } catch { /* not up yet */ }
    await new Promise((r) => setTimeout(r, 100));
  }
  browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const show = async (sse) => {
    const page = await browser.newPage({ viewport: { width: 1000, height: 700 } });
    const pageErrors = [];
    const outside = [];
    page.on('pageerror', (e) => pageErrors.push(String(e)));
    page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); });
    page.on('response', (r) => { if (r.status() >= 400) pageErrors.push(`${r.status()} ${r.url()}`); });
    page.on('request', (r) => { if (!r.url().startsWith(base) && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) outside.push(r.url()); });
    const tilesetUrl = `${base}target/e2e/pyramid/tiles/tileset.json`;
    await page.goto(`${base}tests/e2e/cesium.html?tileset=${encodeURIComponent(tilesetUrl)}&sse=${sse}`);
    await page.waitForFunction(() => window.pyramid && (window.pyramid.error || (window.pyramid.ready && window.pyramid.allLoaded > 0)), null, { timeout: 120000 });
    const state = await page.evaluate(() => window.pyramid);
    assert.equal(state.error, null, `the tileset loads: ${state.error}`);
    assert.deepEqual(state.failed, [], 'no tile fails');
    assert.deepEqual(pageErrors.filter((e) => !/GPU stall|WebGL-/.test(e)), [], 'no page error');
    assert.deepEqual(outside, [], 'no request leaves this machine');
    return { page, loaded: state.loaded.map((u) => u.replace(/^.*\/tiles\//, '')) };
  };

  // Fine: every tile of the deepest level is in view and needed.
  const fine = await show(0.5);
  const deepest = tiles.filter((t) => t.depth === LEVELS - 1).map((t) => t.uri);
  for (const uri of deepest) assert.ok(fine.loaded.includes(uri), `${uri} loads`);
  for (const uri of fine.loaded) assert.ok(tiles.some((t) => t.uri === uri), `${uri} is a tile of the tileset`);
  await fine.page.screenshot({ path: path.join(root, 'target/e2e/pyramid-cesium.png') });
  console.log(`CesiumJS, fine: ${fine.loaded.length} tiles loaded, all ${deepest.length} of level ${LEVELS - 1}`);
  await fine.page.close();

  // Coarse: a screen-space error limit between the root's error and the tileset's (set by the
  // page from the camera's place) needs the root alone.
  const coarse = await show('root');
  assert.deepEqual(coarse.loaded, [tileset.root.content.uri]);
  console.log(`CesiumJS, coarse: the root alone (${coarse.loaded[0]})`);
  await coarse.page.close();
} finally {
  if (browser) await browser.close();
  server.kill();
}
console.log('tiles.test.mjs: 1 passed, 0 failed');
