// End-to-end test of runs in the pool of Web Workers (www/pool.js), in headless Chromium:
// 1. `?workers` sends an untiled run to a worker: NSGA-II on the built-in surface reaches the
//    CLI's front for the same seed exactly (T and E), the status names the workers, the run
//    ends with its trade-off pick drawn, and clicking another member draws it;
// 2. a worker that fails (a job it cannot build) stops the run with a clear message, the
//    page keeps drawing frames, and a valid run afterwards works;
// 3. a 257×257 grid (scripts/terrain.py's fbm) with `?tile=65` runs as 16 tiles in the pool
//    (two workers): a first whole-grid front from the greedy pass, then the NSGA-II pass,
//    ending on the front of the CLI's tiled run with the same seed and tile size; selecting a
//    member draws its mesh, rebuilt from the tiles, with as many triangles as the member's T.
// 4. A 1025×1025 grid with `?tile=257` (greedy insertion, 16 tiles): a member's mesh is built
//    in the pool's mesh worker, not on the page: animation frames keep coming while it is
//    built, and selecting another member while the worker still builds the first ends with the
//    newer member drawn (the older mesh, when it comes, is dropped).
// Needs the CLI (cargo build --bin paretomesh) and www/pkg (bash scripts/build-web.sh).
import { readFileSync, writeFileSync, mkdtempSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';
import { shots, withApp, newPage, realErrors, waitForApp, dropFiles, pixelVariance, frameCount, startFrameLog, stopFrameLog } from './harness.mjs';
import { terrainGrid } from './terrain-grid.mjs';
import { cli, cliFront } from './cli.mjs';


// The CLI's tiled front for `args` on `files` (written to a scratch folder), as [T, E] pairs.
function cliTiledFront(files, args) {
  const dir = mkdtempSync(path.join(tmpdir(), 'pm-'));
  for (const f of files) writeFileSync(path.join(dir, f.name), f.bytes);
  const out = path.join(dir, 'front.json');
  execFileSync(cli, ['run', path.join(dir, files[0].name), ...args, '--out', out], { stdio: ['ignore', 'ignore', 'inherit'] });
  const file = JSON.parse(readFileSync(out, 'utf8'));
  return (file.tiled?.members ?? file.front).map((m) => [m.T, m.E_sum]);
}

const pairs = (flat) => flat.reduce((acc, v, i) => (i % 2 ? acc[acc.length - 1].push(v) : acc.push([v]), acc), []);
const status = (page) => page.locator('#status').textContent();

async function runNsga2(page, { population, generations, seed }) {
  await page.selectOption('#algorithm', 'nsga2');
  await page.fill('#population', String(population));
  await page.fill('#generations', String(generations));
  await page.fill('#seed', String(seed));
  await page.click('#run');
}

await withApp(async ({ browser, url }) => {
  // 1. An untiled run in one worker equals the CLI's run.
  const page = await newPage(browser);
  await page.goto(`${url}?workers`);
  await waitForApp(page);
  await startFrameLog(page);
  await runNsga2(page, { population: 20, generations: 15, seed: 4 });
  await page.waitForFunction(() => /Web Workers/.test(document.getElementById('status').textContent), null, { timeout: 30000 });
  await page.waitForFunction(() => /^done/.test(document.getElementById('status').textContent), null, { timeout: 120000 });
  const frames = await stopFrameLog(page);
  const browserFront = pairs(await page.evaluate(() => window.paretomesh.frontObjectives()));
  const expected = cliFront(['tests/data/jacksboro_65x65.f32', '--algo', 'nsga2', '--pop', '20', '--gens', '15', '--seed', '4']);
  assert.ok(expected.length >= 5, `the CLI front has members (${expected.length})`);
  assert.deepEqual(browserFront, expected, 'the worker run reaches the CLI front exactly (T and E)');
  assert.match(await status(page), /1 of 1 jobs done in 1 Web Workers/);
  assert.ok(await page.evaluate(() => window.paretomesh.selectedObjectives() !== undefined), 'the run ends with a member selected');
  assert.ok(frames.length > 5, `frames kept coming while the worker ran (${frames.length})`);

  // Clicking another member draws it (the click may land on a neighbour of close points).
  const [picked] = await page.evaluate(() => window.paretomesh.selectedObjectives());
  const target = picked > 3 ? 2 : expected.length - 3;
  const [x, y] = await page.evaluate((i) => window.paretomesh.frontPointPosition(i), target);
  const box = await page.locator('#plot').boundingBox();
  await page.mouse.click(box.x + x, box.y + y);
  await page.waitForFunction((i) => window.paretomesh.selectedObjectives()?.[0] !== i, picked, { timeout: 10000 });
  const [clicked, t] = await page.evaluate(() => window.paretomesh.selectedObjectives());
  assert.ok(Math.abs(clicked - target) <= 2, `the clicked member is selected (${clicked}, aimed at ${target})`);
  assert.equal(t, expected[clicked][0], 'its T is the front member\'s');
  assert.equal(await page.evaluate(() => window.paretomesh.shownTriangleCount()), t, 'its mesh is drawn');
  await page.waitForTimeout(300);
  const variance = await pixelVariance(page, await page.locator('#view').screenshot());
  assert.ok(variance > 50, `the selected mesh is drawn (pixel variance ${variance.toFixed(1)})`);
  await page.screenshot({ path: path.join(shots, 'workers-01-untiled.png') });
  assert.deepEqual(realErrors(page), [], 'no page errors');

  // 2. A failing worker: a job whose parameters its algorithm refuses. The page's form never
  // hands out such a job, so the test posts one to the pool's worker script directly, then
  // checks that the pool turns a worker's error into the run's message.
  const failure = await page.evaluate(async () => {
    const worker = new Worker(new URL('./www/pool-worker.js', location.href), { type: 'module' });
    return new Promise((resolve) => {
      worker.onmessage = ({ data }) => { worker.terminate(); resolve(data); };
      worker.postMessage({ run: 1, index: 0, algorithm: 'nsga2', params: '{"population": 3}', surface: { width: 2 } });
    });
  });
  assert.equal(failure.kind, 'error', 'the worker reports an error, not a front');
  assert.match(failure.message, /parsed surface|population/, `the error says what is wrong: ${failure.message}`);
  const before = await frameCount(page).catch(() => 0);
  await startFrameLog(page);
  await page.evaluate(() => {
    const app = window.paretomesh;
    app.setPoolSetup(2, true);
  });
  await runNsga2(page, { population: 20, generations: 15, seed: 5 });
  await page.waitForFunction(() => window.paretomesh.poolRunId() > 0, null, { timeout: 10000 });
  await page.evaluate(() => window.paretomesh.poolFailed(window.paretomesh.poolRunId(), 0, 'the worker ran out of memory'));
  await page.waitForFunction(() => /ran out of memory/.test(document.getElementById('run-message').textContent), null, { timeout: 10000 });
  assert.match(await status(page), /stopped: a worker failed/);
  await page.waitForTimeout(500);
  const after = await stopFrameLog(page);
  assert.ok(after.length > 10, `frames keep coming after the failure (${after.length}, before ${before})`);
  // Run again: a failed run starts from scratch and ends.
  await page.click('#run');
  await page.waitForFunction(() => /^done/.test(document.getElementById('status').textContent), null, { timeout: 120000 });
  assert.equal(await page.locator('#run-message').textContent(), '', 'the message went with the new run');
  assert.deepEqual(realErrors(page), [], 'no page errors');
  await page.close();

  // 3. A tiled grid in the pool.
  const tiled = await newPage(browser);
  await tiled.goto(`${url}?tile=65`);
  await waitForApp(tiled);
  await tiled.evaluate(() => window.paretomesh.setPoolSetup(2, false, 65));
  const { files } = terrainGrid('fbm', 257);
  await dropFiles(tiled, files);
  await tiled.waitForFunction(() => window.paretomesh.surfaceName() === 'fbm_257.f32', null, { timeout: 30000 });
  await runNsga2(tiled, { population: 8, generations: 3, seed: 2 });
  await tiled.waitForFunction(() => /16 tiles \(4×4\) in 2 Web Workers/.test(document.getElementById('status').textContent), null, { timeout: 30000 });
  await tiled.waitForFunction(() => window.paretomesh.frontLength() > 0, null, { timeout: 120000 });
  const firstStatus = await status(tiled);
  await tiled.waitForFunction(() => /^done/.test(document.getElementById('status').textContent), null, { timeout: 300000 });
  assert.match(await status(tiled), /16 with a front, 16 final/);
  const tiledFront = pairs(await tiled.evaluate(() => window.paretomesh.frontObjectives()));
  const expectedTiled = cliTiledFront(files, ['--algo', 'nsga2', '--pop', '8', '--gens', '3', '--seed', '2', '--tile', '65', '--threads', '1']);
  assert.ok(expectedTiled.length >= 10, `the CLI's tiled front has members (${expectedTiled.length})`);
  assert.deepEqual(tiledFront, expectedTiled, `the pool's tiled front is the CLI's (first seen: ${firstStatus})`);
  const [pick] = await tiled.evaluate(() => window.paretomesh.selectedObjectives());
  const member = pick > 3 ? 2 : tiledFront.length - 3;
  const [mx, my] = await tiled.evaluate((i) => window.paretomesh.frontPointPosition(i), member);
  const plot = await tiled.locator('#plot').boundingBox();
  await tiled.mouse.click(plot.x + mx, plot.y + my);
  await tiled.waitForFunction((i) => window.paretomesh.selectedObjectives()?.[0] !== i, pick, { timeout: 10000 });
  const [chosen] = await tiled.evaluate(() => window.paretomesh.selectedObjectives());
  assert.ok(Math.abs(chosen - member) <= 2, `the clicked member is selected (${chosen}, aimed at ${member})`);
  await tiled.waitForFunction(() => Number(document.getElementById('selection-info').dataset.vertices) > 0, null, { timeout: 30000 });
  assert.equal(await tiled.evaluate(() => window.paretomesh.shownTriangleCount()), tiledFront[chosen][0], 'the drawn mesh has the member\'s triangles');
  await tiled.waitForTimeout(300);
  const tiledVariance = await pixelVariance(tiled, await tiled.locator('#view').screenshot());
  assert.ok(tiledVariance > 50, `the tiled member is drawn (pixel variance ${tiledVariance.toFixed(1)})`);
  await tiled.screenshot({ path: path.join(shots, 'workers-02-tiled.png') });
  assert.ok(await tiled.evaluate(() => window.paretomeshPool.log.some((j) => j.kind === 'mesh')), 'the member\'s mesh was built in the mesh worker');
  assert.deepEqual(realErrors(tiled), [], 'no page errors');
  await tiled.close();

  // 4. Meshes built in the mesh worker while the page keeps drawing frames.
  const big = await newPage(browser);
  await big.goto(`${url}?tile=257`);
  await waitForApp(big);
  await big.evaluate(() => window.paretomesh.setPoolSetup(2, false, 257));
  await dropFiles(big, terrainGrid('fbm', 1025).files);
  await big.waitForFunction(() => window.paretomesh.surfaceName() === 'fbm_1025.f32', null, { timeout: 60000 });
  await big.selectOption('#algorithm', 'greedy');
  await big.click('#run');
  await big.waitForFunction(() => /^done/.test(document.getElementById('status').textContent), null, { timeout: 600000, polling: 200 });
  assert.match(await status(big), /16 with a front, 16 final/);
  const bigFront = pairs(await big.evaluate(() => window.paretomesh.frontObjectives()));
  assert.ok(bigFront.length >= 20, `the tiled front has members (${bigFront.length})`);
  // The run ends with its trade-off pick selected; wait until its mesh is drawn.
  await big.waitForFunction(() => !window.paretomesh.meshBuilding() && window.paretomesh.shownTriangleCount() > 0, null, { timeout: 120000 });
  const [first, second] = [Math.floor(bigFront.length * 0.8), Math.floor(bigFront.length * 0.6)];
  const race = await big.evaluate(async ([a, b]) => {
    const app = window.paretomesh;
    const pool = window.paretomeshPool;
    const frame = () => new Promise((r) => requestAnimationFrame(r));
    const meshes = () => pool.log.filter((j) => j.kind === 'mesh').length;
    const [sent, built] = [pool.meshesSent, meshes()];
    app.selectFrontMember(a);
    const building = app.meshBuilding();
    while (pool.meshesSent === sent) await frame();
    // The worker has the first member's job: select the second before its mesh comes.
    const stillBuilding = pool.meshBusy && meshes() === built;
    app.selectFrontMember(b);
    let frames = 0;
    while (app.meshBuilding()) { await frame(); frames++; }
    return { building, stillBuilding, frames, jobs: pool.meshesSent - sent, meshes: meshes() - built,
      selected: app.selectedObjectives(), triangles: app.shownTriangleCount(),
      info: document.getElementById('selection-info').textContent };
  }, [first, second]);
  console.log(`mesh worker: ${race.frames} frames drawn while two meshes were built; ${race.info}`);
  assert.ok(race.building, 'selecting a member starts building its mesh');
  assert.ok(race.stillBuilding, 'the second member was selected while the worker built the first');
  assert.ok(race.frames >= 3, `animation frames kept coming while the meshes were built (${race.frames})`);
  assert.equal(race.jobs, 2, 'both meshes went to the worker');
  assert.equal(race.meshes, 2, 'the worker built both');
  assert.equal(race.selected[0], second, 'the newer member stays selected');
  assert.ok(bigFront[second][0] <= 2000000, 'the member is under the view\'s triangle limit');
  assert.equal(race.triangles, bigFront[second][0], `the newer member is drawn (${race.info})`);
  assert.equal(await big.evaluate(() => Number(document.getElementById('selection-info').dataset.vertices) > 0), true, 'the selection line names its vertices');
  await big.waitForTimeout(300);
  const bigVariance = await pixelVariance(big, await big.locator('#view').screenshot());
  assert.ok(bigVariance > 50, `the member is drawn (pixel variance ${bigVariance.toFixed(1)})`);
  await big.screenshot({ path: path.join(shots, 'workers-03-mesh-worker.png') });
  assert.deepEqual(realErrors(big), [], 'no page errors');
  await big.close();
});
console.log('workers e2e: ok');
