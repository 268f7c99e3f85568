// Measures the default method in the browser app (headless Chromium, WebGL2), as a benchmark:
// it prints figures and asserts nothing about time.
//
//   node scripts/bench-browser.mjs [SURFACE_257.ply] [GRID_1025.f32]
//
// 1. Drops a 257×257 PLY (when none is given, `fractal_257` of `bash scripts/make-grids.sh`:
//    scripts/terrain.py's fbm, seed 1, made here), runs greedy insertion to get its front, then
//    runs the default method and reports: the time from Run to the first front (the greedy
//    seed), the time until the front's normalised hypervolume exceeds greedy insertion's, and
//    the frame intervals while it runs (median, 95th percentile).
// 2. Drops a 1025×1025 .f32 grid with its .json sidecar (`fractal_1025` when none is given) and
//    reports the time from the drop to the surface drawn and to the first front after Run.
// Needs the built app (bash scripts/build-web.sh).
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { withApp, newPage, waitForApp, dropFiles, startFrameLog, frameCount, stopFrameLog } from '../tests/e2e/harness.mjs';
import { terrainGrid } from '../tests/e2e/terrain-grid.mjs';

function gridPly(w, h, z) {
  const lines = ['ply', 'format ascii 1.0', `element vertex ${w * h}`, 'property float x',
    'property float y', 'property float z', `element face ${2 * (w - 1) * (h - 1)}`,
    'property list uchar int vertex_indices', 'end_header'];
  for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) lines.push(`${x} ${y} ${z[y * w + x]}`);
  for (let y = 0; y < h - 1; y++) {
    for (let x = 0; x < w - 1; x++) {
      const a = y * w + x;
      lines.push(`3 ${a} ${a + 1} ${a + w}`, `3 ${a + 1} ${a + w + 1} ${a + w}`);
    }
  }
  return Buffer.from(lines.join('\n') + '\n');
}

/// Hypervolume of `front` ([T, E] pairs) in normalised objectives (T / full T, E / E0) against
/// the reference point (1.1, 1.1).
function hypervolume(front, fullT, e0) {
  const pts = front.map(([t, e]) => [t / fullT, e / e0]).filter(([t, e]) => t < 1.1 && e < 1.1)
    .sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  const staircase = [];
  for (const p of pts) if (!staircase.length || p[1] < staircase[staircase.length - 1][1]) staircase.push(p);
  let hv = 0;
  staircase.forEach(([t, e], i) => { hv += ((staircase[i + 1]?.[0] ?? 1.1) - t) * (1.1 - e); });
  return hv;
}

const pairs = (flat) => { const out = []; for (let i = 0; i < flat.length; i += 2) out.push([flat[i], flat[i + 1]]); return out; };
const pct = (xs, p) => { const s = [...xs].sort((a, b) => a - b); return s[Math.min(s.length - 1, Math.floor(p * s.length))]; };

const [plyArg, gridArg] = process.argv.slice(2);
const ply = plyArg
  ? { name: path.basename(plyArg), bytes: readFileSync(plyArg) }
  : { name: 'fractal_257.ply', bytes: gridPly(257, 257, terrainGrid('fbm', 257, { name: 'fractal_257' }).z) };
const big = gridArg
  ? [{ name: path.basename(gridArg), bytes: readFileSync(gridArg) },
    { name: path.basename(gridArg).replace(/\.f32$/, '.json'), bytes: readFileSync(gridArg.replace(/\.f32$/, '.json')) }]
  : terrainGrid('fbm', 1025, { name: 'fractal_1025' }).files;

async function runUntil(page, algorithm, done, timeout) {
  await page.selectOption('#algorithm', algorithm);
  await startFrameLog(page);
  const t0 = Date.now();
  await page.click('#run');
  await page.waitForFunction(done, null, { timeout, polling: 50 });
  return Date.now() - t0;
}

await withApp(async ({ browser, url }) => {
  const page = await newPage(browser);
  await page.goto(url);
  await waitForApp(page);

  // 1. The 257×257 PLY.
  await dropFiles(page, [ply]);
  await page.waitForFunction((n) => window.paretomesh.surfaceName() === n, ply.name, { timeout: 120000 });
  const info = await page.locator('#surface-info').textContent();
  const [, w, h] = info.match(/(\d+)×(\d+) grid/).map(Number);
  const fullT = 2 * (w - 1) * (h - 1);
  const greedyMs = await runUntil(page, 'greedy', () => document.getElementById('status').textContent.startsWith('done'), 600000);
  const greedy = pairs(await page.evaluate(() => window.paretomesh.frontObjectives()));
  // E0: the corner-only mesh's E (greedy insertion's first snapshot).
  const e0 = (greedy.find(([t]) => t === 2) ?? greedy.reduce((a, b) => (a[1] > b[1] ? a : b)))[1];
  const hvGreedy = hypervolume(greedy, fullT, e0);
  await stopFrameLog(page);

  await page.selectOption('#algorithm', 'memetic');
  const seedMs = await runUntil(page, 'memetic', () => window.paretomesh.frontLength() > 0, 600000);
  const seedFrames = await frameCount(page);
  const t1 = Date.now();
  let beatMs = null, hv = 0, doneFrames = null;
  // Runs for 20 s (or until the front beats greedy insertion's, if later), sampling the front.
  while (Date.now() - t1 < 120000 && (beatMs === null || Date.now() - t1 < 20000)) {
    hv = hypervolume(pairs(await page.evaluate(() => window.paretomesh.frontObjectives())), fullT, e0);
    if (beatMs === null && hv > hvGreedy) beatMs = seedMs + Date.now() - t1;
    if (doneFrames === null && (await page.locator('#status').textContent()).startsWith('done')) {
      doneFrames = await frameCount(page);
    }
    await page.waitForTimeout(250);
  }
  const all = await stopFrameLog(page);
  // Frames while the optimiser runs: from Run until the status says done.
  const frames = all.slice(2, doneFrames ?? all.length);
  const after = all.slice(seedFrames, doneFrames ?? all.length);
  const frameLine = (xs) => `${xs.length} frames, median ${pct(xs, 0.5).toFixed(1)} ms, 95th percentile ${pct(xs, 0.95).toFixed(1)} ms, ${(100 * xs.filter((f) => f < 20).length / xs.length).toFixed(1)} % under 20 ms`;
  await page.click('#pause');
  console.log(`${ply.name}: ${w}×${h}; greedy insertion ${greedyMs} ms in the app, hypervolume ${hvGreedy.toFixed(4)}`);
  console.log(`  default method: first front ${seedMs} ms after Run; front beats greedy insertion's at ${beatMs ?? '> ' + (seedMs + 120000)} ms (hypervolume ${hv.toFixed(4)})`);
  console.log(`  frames from Run until done: ${frameLine(frames)}`);
  console.log(`  frames after the first front: ${frameLine(after)}`);
  console.log(`  status: ${await page.locator('#status').textContent()}`);

  // 2. The 1025×1025 grid.
  const t2 = Date.now();
  await dropFiles(page, big);
  await page.waitForFunction((n) => window.paretomesh.surfaceName() === n, big[0].name, { timeout: 300000, polling: 50 });
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const loadMs = Date.now() - t2;
  const frontMs = await runUntil(page, 'memetic', () => window.paretomesh.frontLength() > 0, 600000);
  await stopFrameLog(page);
  await page.click('#pause');
  console.log(`${big[0].name}: loaded and drawn ${loadMs} ms after the drop; first front ${frontMs} ms after Run (${loadMs + frontMs} ms in all)`);
});
