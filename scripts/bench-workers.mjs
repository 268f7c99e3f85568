// Measures a tiled run in the browser app's pool of Web Workers, as a benchmark: it prints
// figures and asserts nothing about time.
//
//   node scripts/bench-workers.mjs FILE [--tile N] [--seconds S] [--algo A] [--no-load]
//
// Chooses FILE (a GeoTIFF, or a .f32 grid with its .json sidecar beside it) in the app's file
// picker, keeps a CPU-bound process busy on one core (unless --no-load), and reports: the time
// from Run to the first whole-grid front, the frame intervals while the run goes on for S
// seconds (default 30), the tiles done by then, the workers' time per job, the page's own time
// per step (`mainThreadCosts`), and the time from clicking a member of the front to its mesh
// drawn, with the frames the page drew meanwhile. Needs the built app (bash scripts/build-web.sh).
import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { withApp, newPage, waitForApp, startFrameLog, stopFrameLog } from '../tests/e2e/harness.mjs';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const at = args.indexOf(name);
  return at >= 0 ? args[at + 1] : fallback;
};
const file = args.find((a, i) => !a.startsWith('--') && !args[i - 1]?.startsWith('--'));
if (!file) {
  console.error('usage: node scripts/bench-workers.mjs FILE [--tile N] [--seconds S] [--algo A] [--no-load]');
  process.exit(2);
}
const tile = Number(option('--tile', 0));
const seconds = Number(option('--seconds', 30));
const algorithm = option('--algo', 'memetic');
const files = [path.resolve(file)];
const sidecar = file.replace(/\.f32$/, '.json');
if (file.endsWith('.f32') && existsSync(sidecar)) files.push(path.resolve(sidecar));

const pct = (xs, p) => { const s = [...xs].sort((a, b) => a - b); return s[Math.min(s.length - 1, Math.floor(p * s.length))]; };
const frameLine = (xs) => `${xs.length} frames, median ${pct(xs, 0.5).toFixed(1)} ms, 95th percentile ${pct(xs, 0.95).toFixed(1)} ms, ${(100 * xs.filter((f) => f < 20).length / xs.length).toFixed(1)} % under 20 ms`;

function printCosts(costs) {
  const rows = Object.entries(costs).sort((a, b) => b[1].total - a[1].total);
  for (const [name, c] of rows) console.log(`    ${name.padEnd(20)} ${String(c.count).padStart(6)} ${c.total.toFixed(0).padStart(8)} ${c.max.toFixed(1).padStart(8)}`);
}

// A CPU-bound job on the machine's other core while the app runs.
const load = args.includes('--no-load') ? null : spawn(process.execPath, ['-e', 'for (;;) {}'], { stdio: 'ignore' });
try {
  await withApp(async ({ browser, url }) => {
    const page = await newPage(browser);
    await page.goto(tile ? `${url}?tile=${tile}` : url);
    await waitForApp(page);
    const t0 = Date.now();
    await page.setInputFiles('#file-input', files);
    const name = path.basename(file);
    // A file the app would resample opens the import dialog: take the size it offers.
    await page.waitForFunction((n) => window.paretomesh.surfaceName() === n || document.getElementById('import-dialog').open, name, { timeout: 600000, polling: 100 });
    if (await page.evaluate(() => document.getElementById('import-dialog').open)) {
      console.log(`import dialog: ${await page.locator('#import-summary').textContent()} · offers ${await page.inputValue('#import-width')}×${await page.inputValue('#import-height')}`);
      await page.click('#import-use');
      await page.waitForFunction((n) => window.paretomesh.surfaceName() === n, name, { timeout: 600000, polling: 100 });
    }
    const loadMs = Date.now() - t0;
    console.log(`${name}: ${await page.locator('#surface-info').textContent()} · loaded ${loadMs} ms after it was chosen`);

    await page.selectOption('#algorithm', algorithm);
    await page.evaluate(() => window.paretomesh.mainThreadCosts(true));
    await startFrameLog(page);
    const t1 = Date.now();
    await page.click('#run');
    await page.waitForFunction(() => window.paretomesh.frontLength() > 0 || /stopped/.test(document.getElementById('status').textContent), null, { timeout: 600000, polling: 50 });
    const firstMs = Date.now() - t1;
    const firstStatus = await page.locator('#status').textContent();
    const remaining = seconds * 1000 - (Date.now() - t1);
    if (remaining > 0) await page.waitForTimeout(remaining);
    const frames = (await stopFrameLog(page)).slice(2);
    console.log(`${algorithm}: first whole-grid front ${firstMs} ms after Run (${await page.evaluate(() => window.paretomesh.frontLength())} members now)`);
    console.log(`  at the first front: ${firstStatus}`);
    console.log(`  after ${seconds} s: ${await page.locator('#status').textContent()}`);
    console.log(`  frames while it runs${load ? ', one core busy with another process' : ''}: ${frameLine(frames)}`);
    console.log(`  run message: ${JSON.stringify(await page.locator('#run-message').textContent())}`);
    const log = await page.evaluate(() => window.paretomeshPool?.log ?? []);
    const tiles = log.filter((j) => j.kind === 'tile');
    if (tiles.length) {
      console.log(`  tile jobs done: ${tiles.length}; worker ms per job: ${tiles.map((j) => Math.round(j.ms)).join(' ')}`);
      console.log(`  tile fronts posted: ${(tiles.reduce((a, j) => a + j.bytes, 0) / 1e6).toFixed(1)} MB of JSON in all`);
    }
    console.log('  main-thread time per step while it ran (count, total ms, longest ms):');
    printCosts(JSON.parse(await page.evaluate(() => window.paretomesh.mainThreadCosts(true))));

    // Select a member of the front and time its mesh drawn.
    const n = await page.evaluate(() => window.paretomesh.frontLength());
    if (n > 0) {
      const member = Math.floor(n / 2);
      const [x, y] = await page.evaluate((i) => window.paretomesh.frontPointPosition(i), member);
      const box = await page.locator('#plot').boundingBox();
      await startFrameLog(page);
      const t2 = Date.now();
      await page.mouse.click(box.x + x, box.y + y);
      // The click may land on a neighbour of close points: any member selected and drawn.
      await page.waitForFunction(() => window.paretomesh.selectedObjectives()?.[0] >= 0 && !window.paretomesh.meshBuilding() && window.paretomesh.shownTriangleCount() > 0, null, { timeout: 300000, polling: 50 });
      await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
      const drawnMs = Date.now() - t2;
      const during = await stopFrameLog(page);
      console.log(`  member ${(await page.evaluate(() => window.paretomesh.selectedObjectives()))[0]} (aimed at ${member}) drawn ${drawnMs} ms after the click: ${await page.locator('#selection-info').textContent()}`);
      console.log(`  frames from the click to the mesh drawn: ${frameLine(during)}`);
      const meshes = (await page.evaluate(() => window.paretomeshPool?.log ?? [])).filter((j) => j.kind === 'mesh');
      if (meshes.length) console.log(`  mesh worker: ${meshes.map((j) => Math.round(j.ms)).join(' ')} ms per mesh`);
      console.log('  main-thread time per step from the click to the mesh drawn:');
      printCosts(JSON.parse(await page.evaluate(() => window.paretomesh.mainThreadCosts(true))));
    }
    await page.screenshot({ path: path.join('target', 'bench-workers.png') });
  });
} finally {
  load?.kill();
}
