// End-to-end test of the browser app in headless Chromium (playwright-core driving
// /usr/bin/chromium). Serves the built app (www/pkg must exist: scripts/build-web.sh), then:
// first load → drop a surface → the form shows the fields each method reads → run NSGA-II
// until the front has ≥ 10 points → click a front point → the 3-D canvas is not blank →
// export PLY and, with the error map, glTF and check them → drop a corrupt file and check the
// message while the previous surface stays.
// Screenshots go to target/e2e/. Prints (does not assert) frame timing, time to first paint
// and evaluations/s.
import { readFileSync } from 'node:fs';
import path from 'node:path';
import assert from 'node:assert/strict';
import { root, shots, withApp, newPage, realErrors, waitForApp, dropFiles, pixelVariance, wavyObj, startFrameLog, stopFrameLog } from './harness.mjs';

const DROP_FILES = (process.env.E2E_DROP ?? 'tests/data/volcano_87x61.ply').split(',');


const status = (page) => page.locator('#status').textContent();

await withApp(async ({ browser, url }) => {
  const page = await newPage(browser);

  // 1. First load: the built-in surface in 3-D with its statistics.
  await page.goto(url);
  await waitForApp(page);
  const firstPaint = await page.evaluate(() => performance.getEntriesByName('paretomesh-first-paint')[0].startTime);
  const info = await page.locator('#surface-info').textContent();
  assert.match(info, /jacksboro_65x65 · 65×65 grid · 4225 points · full mesh 8192 triangles/);
  const backend = await page.locator('#backend').textContent();
  assert.equal(backend, 'WebGL2', `headless Chromium without WebGPU flags must use WebGL2, got ${backend}`);
  await page.screenshot({ path: path.join(shots, '01-first-load.png') });
  const firstVariance = await pixelVariance(page, await page.locator('#view').screenshot());
  assert.ok(firstVariance > 50, `the built-in surface is drawn (pixel variance ${firstVariance.toFixed(1)})`);

  // 2. Drop a surface.
  const files = DROP_FILES.map((f) => ({ name: path.basename(f), bytes: readFileSync(path.join(root, f)) }));
  await dropFiles(page, files);
  await page.waitForFunction((name) => window.paretomesh.surfaceName() === name, files[0].name, { timeout: 30000 });
  const dropped = await page.locator('#surface-info').textContent();
  assert.match(dropped, /87×61 grid · 5307 points/);
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(shots, '02-dropped.png') });

  // The form shows only the fields the selected method reads: the memetic method (the
  // default) only the seed, greedy insertion none, NSGA-II all of them.
  const shown = (ids) => Promise.all(ids.map((id) => page.locator(`#${id}`).isVisible()));
  const fields = ['population', 'generations', 'crossover', 'crossover-probability', 'mutation-probability', 'seed'];
  assert.equal(await page.inputValue('#algorithm'), 'memetic');
  assert.deepEqual(await shown(fields), [false, false, false, false, false, true], 'memetic: only the seed');
  // Compare mode runs the two GAs with the form's parameters, so it shows every field.
  await page.check('#compare-on');
  assert.deepEqual(await shown(fields), [true, true, true, true, true, true], 'compare mode: every field');
  await page.uncheck('#compare-on');
  assert.deepEqual(await shown(fields), [false, false, false, false, false, true], 'memetic again');
  await page.selectOption('#algorithm', 'greedy');
  assert.deepEqual(await shown(fields), [false, false, false, false, false, false], 'greedy insertion: no field');

  // 3. Run NSGA-II until the front has at least 10 points, measuring frame intervals.
  await page.selectOption('#algorithm', 'nsga2');
  assert.deepEqual(await shown(fields), [true, true, true, true, true, true], 'NSGA-II: every field');
  await startFrameLog(page);
  await page.click('#run');
  await page.waitForFunction(
    () => window.paretomesh.frontLength() >= 10 || document.getElementById('run-message').textContent !== '',
    null, { timeout: 120000 });
  assert.equal(await page.locator('#run-message').textContent(), '', 'NSGA-II runs');
  await page.waitForTimeout(1500); // a little longer, for the frame statistics
  const frames = await stopFrameLog(page);
  const runStatus = await status(page);
  await page.click('#pause');
  await page.screenshot({ path: path.join(shots, '03-front.png') });

  // 4. Click a front point: it becomes the selection and is drawn.
  const n = await page.evaluate(() => window.paretomesh.frontLength());
  const pick = Math.floor(n / 2);
  const [x, y] = await page.evaluate((i) => window.paretomesh.frontPointPosition(i), pick);
  const box = await page.locator('#plot').boundingBox();
  await page.mouse.click(box.x + x, box.y + y);
  await page.waitForFunction(() => window.paretomesh.selectedVertexCount() !== undefined, null, { timeout: 10000 });
  const vertices = await page.evaluate(() => window.paretomesh.selectedVertexCount());
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(shots, '04-selected.png') });
  const viewShot = await page.locator('#view').screenshot({ path: path.join(shots, '04-view.png') });
  const variance = await pixelVariance(page, viewShot);
  assert.ok(variance > 50, `the 3-D canvas is not blank (pixel variance ${variance.toFixed(1)})`);
  for (const id of ['show-error', 'show-kept', 'show-original']) await page.check(`#${id}`);
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(shots, '05-error-map.png') });

  // 5. Export PLY: it parses and has the selected solution's vertex count.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-ply')]);
  const ply = readFileSync(await download.path(), 'utf8');
  const header = ply.slice(0, ply.indexOf('end_header\n'));
  const nv = Number(/element vertex (\d+)/.exec(header)[1]);
  const nf = Number(/element face (\d+)/.exec(header)[1]);
  const body = ply.slice(header.length + 'end_header\n'.length).trim().split('\n');
  assert.equal(nv, vertices, 'exported vertices = selected vertices');
  assert.equal(body.length, nv + nf, 'one line per vertex and face');
  for (const line of body.slice(0, nv)) {
    const v = line.split(' ').map(Number);
    assert.ok(v.length === 3 && v.every(Number.isFinite), `vertex line ${line}`);
  }
  for (const line of body.slice(nv)) {
    const f = line.split(' ').map(Number);
    assert.ok(f[0] === 3 && f.slice(1).every((i) => Number.isInteger(i) && i >= 0 && i < nv), `face line ${line}`);
  }

  // Binary glTF with the error map shown: the header, the JSON chunk (one mesh, the selected
  // vertices, normals and COLOR_0) and a binary chunk holding every accessor.
  const [glbDownload] = await Promise.all([page.waitForEvent('download'), page.click('#export-glb')]);
  assert.match(glbDownload.suggestedFilename(), /\.glb$/);
  const glb = readFileSync(await glbDownload.path());
  assert.equal(glb.toString('latin1', 0, 4), 'glTF', 'glTF magic');
  assert.equal(glb.readUInt32LE(4), 2, 'glTF version 2');
  assert.equal(glb.readUInt32LE(8), glb.length, 'the header gives the file length');
  const jsonLength = glb.readUInt32LE(12);
  assert.equal(glb.toString('latin1', 16, 20), 'JSON');
  const gltf = JSON.parse(glb.toString('utf8', 20, 20 + jsonLength));
  assert.equal(glb.toString('latin1', 24 + jsonLength, 28 + jsonLength), 'BIN\0');
  const binLength = glb.readUInt32LE(20 + jsonLength);
  assert.equal(gltf.meshes.length, 1);
  const attributes = gltf.meshes[0].primitives[0].attributes;
  assert.equal(gltf.accessors[attributes.POSITION].count, vertices, 'glb vertices = selected vertices');
  assert.equal(gltf.accessors[attributes.NORMAL].count, vertices);
  assert.equal(gltf.accessors[attributes.COLOR_0].count, vertices, 'the error map as vertex colours');
  assert.equal(gltf.accessors[gltf.meshes[0].primitives[0].indices].count % 3, 0);
  for (const view of gltf.bufferViews) assert.ok((view.byteOffset ?? 0) + view.byteLength <= binLength, 'views inside the binary chunk');

  // The front as front.json (the format of `paretomesh run --out`) and CSV.
  const frontNow = await page.evaluate(() => window.paretomesh.frontLength());
  const [jsonDownload] = await Promise.all([page.waitForEvent('download'), page.click('#export-json')]);
  const run = JSON.parse(readFileSync(await jsonDownload.path(), 'utf8'));
  assert.equal(run.algorithm, 'nsga2');
  assert.equal(run.seed, 1);
  assert.deepEqual([run.grid.width, run.grid.height], [87, 61]);
  assert.equal(run.front.length, frontNow);
  // As `paretomesh run` writes it by default: the kept points (packed, or as a diff with the
  // member before), which determine the triangles.
  assert.equal(typeof run.front[0].kept_packed, 'string', 'the first member is packed whole');
  assert.ok(run.front.every((m) => m.triangles === undefined && typeof (m.kept_packed ?? m.kept_diff) === 'string' && m.T >= 2), 'members list their kept points');
  const [csvDownload] = await Promise.all([page.waitForEvent('download'), page.click('#export-csv')]);
  const csv = readFileSync(await csvDownload.path(), 'utf8').trim().split('\n');
  assert.equal(csv[0], 'T,E_sum,E_max,kept');
  assert.equal(csv.length - 1, frontNow);

  // 6. A corrupt file: a clear message next to the drop zone; surface and selection stay.
  const before = await page.locator('#surface-info').textContent();
  await dropFiles(page, [{ name: 'broken.ply', bytes: Buffer.from('ply\nformat ascii 1.0\nelement vertex 99\nend_header\n1 2\n') }]);
  await page.waitForFunction(() => document.querySelector('#load-message.error') !== null, null, { timeout: 10000 });
  const message = await page.locator('#load-message').textContent();
  assert.match(message, /broken\.ply/);
  assert.equal(await page.locator('#surface-info').textContent(), before);
  assert.equal(await page.evaluate(() => window.paretomesh.selectedVertexCount()), vertices);
  await page.screenshot({ path: path.join(shots, '06-corrupt-file.png') });

  // 7. A mesh that is not a grid opens the projection dialog; its choices shape the grid.
  await dropFiles(page, [{ name: 'wavy.obj', bytes: Buffer.from(wavyObj(30, 20)) }]);
  await page.waitForSelector('#import-dialog[open]', { timeout: 10000 });
  await page.screenshot({ path: path.join(shots, '07-import-dialog.png') });
  await page.selectOption('#import-projection', 'planar');
  await page.fill('#import-width', '40');
  await page.fill('#import-height', '25');
  await page.click('#import-use');
  await page.waitForFunction(() => window.paretomesh.surfaceName() === 'wavy.obj', null, { timeout: 10000 });
  assert.match(await page.locator('#surface-info').textContent(), /40×25 grid · 1000 points/);
  assert.match(await page.locator('#surface-source').textContent(), /planar projection/);
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(shots, '08-resampled.png') });

  assert.deepEqual(realErrors(page), [], 'no page errors');

  const within = frames.filter((d) => d <= 20).length / Math.max(1, frames.length);
  const evalsPerSecond = /([\d.]+) evaluations\/s/.exec(runStatus)?.[1];
  console.log(`e2e ok: first paint ${firstPaint.toFixed(0)} ms after navigation start; ` +
    `${(100 * within).toFixed(1)} % of ${frames.length} frames within 20 ms while the GA ran; ` +
    `${evalsPerSecond} evaluations/s in the browser; front ${n} points; selected ${vertices} vertices; ` +
    `status: ${runStatus}; corrupt file message: ${message}`);
});
