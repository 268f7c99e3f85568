// Terrain in a real viewer, in both formats. The CLI's debug build (target/debug/paretomesh)
// writes tilesets of the EPSG:4326 Jacksboro DEM straight from the GeoTIFF (greedy insertion
// tile by tile) to target/e2e/terrain (quantized-mesh) and target/e2e/terrain-3dtiles (3D
// Tiles terrain); a small node server hands the .terrain files out gzip-encoded, as a terrain
// server does; CesiumJS (npm `cesium`, offline: no Ion token, no base layer) loads them with
// CesiumTerrainProvider and Cesium3DTilesTerrainProvider in headless Chromium; the glbs pass
// the Khronos glTF validator. Checks, for each: tiles load at
// several zoom levels as the camera comes down, no request fails or leaves this machine, no
// page error, and heights sampled at the DEM's own sample points (sampleTerrain at each level of
// the DEM's tiles, sampleTerrainMostDetailed) match the DEM within that level's geometric
// error (plus the DEM's own change across half a sample, for the resampling onto the scheme).
import { chromium } from 'playwright-core';
import { execFileSync } from 'node:child_process';
import { createServer } from 'node:http';
import { mkdirSync, rmSync, readFileSync, readdirSync, existsSync, statSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';
import assert from 'node:assert/strict';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const cli = path.join(process.env.CARGO_TARGET_DIR ?? path.join(root, 'target'), 'debug/paretomesh');
assert.ok(existsSync(cli), 'build the CLI first: cargo build');
const out = path.join(root, 'target/e2e/terrain');
const out3d = path.join(root, 'target/e2e/terrain-3dtiles');
for (const o of [out, out3d]) rmSync(o, { recursive: true, force: true });
mkdirSync(path.dirname(out), { recursive: true });

// 1. The tilesets, straight from the DEM.
const dem = path.join(root, 'tests/data/jacksboro_65x65_wgs84.tif');
execFileSync(cli, ['tiles', dem, '--format', 'quantized-mesh', '--algo', 'greedy', '--water-mask', '--out', out], { stdio: 'inherit' });
execFileSync(cli, ['tiles', dem, '--format', '3dtiles-terrain', '--algo', 'greedy', '--water-mask', '--out', out3d], { stdio: 'inherit' });
const layer = JSON.parse(readFileSync(path.join(out, 'layer.json'), 'utf8'));
const tileset = JSON.parse(readFileSync(path.join(out3d, 'tileset.json'), 'utf8'));
const formats = [
  { name: 'quantized-mesh', key: 'layer', url: 'target/e2e/terrain/', tile: /\/(\d+)\/(\d+)\/(\d+)\.terrain/, levels: layer.paretomesh.levels },
  { name: '3dtiles-terrain', key: 'tileset', url: 'target/e2e/terrain-3dtiles/tileset.json', tile: /terrain-3dtiles\/[01]\/(\d+)\/(\d+)\/(\d+)\.glb/, levels: tileset.extras.paretomesh.levels },
];
for (const f of formats) {
  f.demLevels = f.levels.filter((l) => l.bound !== null);
  assert.ok(f.demLevels.length >= 2, `${f.name}: the DEM has at least two levels of its own`);
}

// Every glb of the 3D Tiles terrain passes the Khronos glTF validator (CESIUM_tile_edges is
// an extension it does not know: a warning, not an error).
const validator = (await import('gltf-validator')).default;
let glbs = 0;
let glbErrors = 0;
const walk = (dir) => readdirSync(dir, { withFileTypes: true }).flatMap((e) => (e.isDirectory() ? walk(path.join(dir, e.name)) : [path.join(dir, e.name)]));
for (const file of walk(out3d).filter((f) => f.endsWith('.glb'))) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), { uri: file });
  if (report.issues.numErrors > 0) console.log(file, JSON.stringify(report.issues.messages.slice(0, 3)));
  glbErrors += report.issues.numErrors;
  glbs += 1;
}
assert.ok(glbs > 10, `${glbs} glbs`);
assert.equal(glbErrors, 0, 'the 3D Tiles terrain glbs pass the glTF validator');
console.log(`glTF validator: ${glbs} 3D Tiles terrain glbs, no errors`);

// The DEM's heights at its sample centres (gdal_translate -a_ullr -84.41 36.73 -84.08 36.45 of
// jacksboro_65x65.f32, row 0 north).
const raw = readFileSync(path.join(root, 'tests/data/jacksboro_65x65.f32'));
const N = 65;
const z = (i, j) => raw.readFloatLE(4 * (j * N + i));
const lon = (i) => -84.41 + (i + 0.5) * 0.33 / N;
const lat = (j) => 36.73 - (j + 0.5) * 0.28 / N;
const samples = [];
for (let j = 4; j < N - 4; j += 7) for (let i = 4; i < N - 4; i += 7) {
  let change = 0;
  for (const [di, dj] of [[1, 0], [-1, 0], [0, 1], [0, -1]]) change = Math.max(change, Math.abs(z(i + di, j + dj) - z(i, j)));
  samples.push({ p: [lon(i), lat(j)], z: z(i, j), slack: change / 2 });
}

// 2. A server for the repository (Cesium) and the tileset, .terrain gzip-encoded.
const types = { '.js': 'text/javascript', '.html': 'text/html', '.css': 'text/css', '.json': 'application/json', '.wasm': 'application/wasm' };
const server = createServer((req, res) => {
  const url = new URL(req.url, 'http://x');
  const file = path.join(root, decodeURIComponent(url.pathname));
  if (!file.startsWith(root) || !existsSync(file) || statSync(file).isDirectory()) { res.writeHead(404); res.end(); return; }
  const headers = { 'Content-Type': types[path.extname(file)] ?? 'application/octet-stream' };
  if (file.endsWith('.terrain')) { headers['Content-Type'] = 'application/vnd.quantized-mesh'; headers['Content-Encoding'] = 'gzip'; }
  res.writeHead(200, headers);
  res.end(readFileSync(file));
});
await new Promise((r) => server.listen(0, '127.0.0.1', r));
const base = `http://127.0.0.1:${server.address().port}/`;
let browser;
try {
  browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  for (const f of formats) {
    const page = await browser.newPage({ viewport: { width: 900, height: 600 } });
    const errors = [];
    const outside = [];
    const terrainRequests = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    page.on('response', (r) => { if (r.status() >= 400) errors.push(`${r.status()} ${r.url()}`); });
    page.on('requestfailed', (r) => errors.push(`failed ${r.url()}`));
    page.on('request', (r) => {
      const u = r.url();
      if (!u.startsWith(base) && !u.startsWith('data:') && !u.startsWith('blob:')) outside.push(u);
      const m = u.match(f.tile);
      if (m) terrainRequests.push(Number(m[1]));
    });
    await page.goto(`${base}tests/e2e/terrain.html?${f.key}=${encodeURIComponent(base + f.url)}`);
    await page.waitForFunction(() => window.terrain && (window.terrain.ready || window.terrain.error), null, { timeout: 120000 });
    assert.equal(await page.evaluate(() => window.terrain.error), null);

    // Down from space to the DEM: every view's tiles load.
    const [cx, cy] = [-84.245, 36.59];
    for (const height of [8e6, 4e5, 4e4, 8e3]) {
      assert.ok(await page.evaluate(([x, y, h]) => window.terrain.view(x, y, h), [cx, cy, height]), `tiles load from ${height} m`);
    }
    await page.screenshot({ path: path.join(root, `target/e2e/${f.name}-cesium.png`) });
    const zooms = [...new Set(terrainRequests)].sort((a, b) => a - b);
    console.log(`${f.name}: tiles requested at zooms ${zooms.join(', ')} (${terrainRequests.length} requests)`);
    assert.ok(zooms.length >= 3, `tiles load at several zoom levels: ${zooms}`);
    assert.ok(zooms.includes(f.demLevels[0].zoom), 'the DEM\'s root tiles load');

    // Heights at every DEM level, and the most detailed.
    const points = samples.map((s) => s.p);
    for (const level of f.demLevels) {
      const got = await page.evaluate(([p, l]) => window.terrain.sample(p, l), [points, level.zoom]);
      let worst = 0;
      samples.forEach((s, k) => {
        const off = Math.abs(got[k] - s.z);
        worst = Math.max(worst, off);
        assert.ok(off <= level.geometricError + s.slack + 1e-3, `zoom ${level.zoom} at ${s.p}: ${got[k]} vs the DEM's ${s.z} (error ${level.geometricError}, slack ${s.slack})`);
      });
      console.log(`${f.name} zoom ${level.zoom}: ${samples.length} heights within the level's geometric error ${level.geometricError.toFixed(2)} m (largest difference ${worst.toFixed(2)} m)`);
    }
    const finest = f.demLevels[f.demLevels.length - 1];
    const detailed = await page.evaluate((p) => window.terrain.sample(p), points);
    samples.forEach((s, k) => assert.ok(Math.abs(detailed[k] - s.z) <= finest.geometricError + s.slack + 1e-3, `most detailed at ${s.p}: ${detailed[k]} vs ${s.z}`));
    console.log(`${f.name} sampleTerrainMostDetailed: ${samples.length} heights within ${finest.geometricError.toFixed(2)} m`);

    assert.deepEqual(errors.filter((e) => !/GPU stall|WebGL-/.test(e)), [], 'no failed request, no page error');
    assert.deepEqual(outside, [], 'no request leaves this machine');
    await page.close();
  }
} finally {
  if (browser) await browser.close();
  server.close();
}
console.log('terrain.test.mjs: 2 passed, 0 failed');
