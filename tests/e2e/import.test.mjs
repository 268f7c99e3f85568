// End-to-end test of GeoTIFF and closed-mesh import in headless Chromium (playwright-core
// driving /usr/bin/chromium). Serves the built app (www/pkg must exist: scripts/build-web.sh),
// then: a GeoTIFF DEM with nodata cells from tests/data loads as it is, with its
// georeferencing and filled cells reported → a small NSGA-II run to the end selects the
// knee and shows it, and its PLY export lies in the DEM's map coordinates → a
// GeoTIFF over the grid limit opens the import dialog with its georeferencing, and the chosen
// grid size is used → a closed, thick mesh (folding in every projection) opens the dialog on
// its outer surface, saying how much of the grid was covered more than once. Screenshots go
// to target/e2e/.
import { readFileSync } from 'node:fs';
import path from 'node:path';
import assert from 'node:assert/strict';
import { root, shots, withApp, newPage, realErrors, waitForApp, dropFiles, pixelVariance, int16GeoTiff, thickTubeObj } from './harness.mjs';

await withApp(async ({ browser, url }) => {
  const page = await newPage(browser);
  await page.goto(url);
  await waitForApp(page);
  assert.match(await page.locator('#file-input').getAttribute('accept'), /\.tif,\.tiff/, 'the picker offers GeoTIFFs');

  // 1. A GeoTIFF DEM (Int16, LZW, 14 nodata cells, georeferenced) loads with no dialog.
  const dem = 'volcano_87x61_int16_lzw_nodata.tif';
  await dropFiles(page, [{ name: dem, bytes: readFileSync(path.join(root, 'tests/data', dem)) }]);
  await page.waitForFunction((name) => window.paretomesh.surfaceName() === name, dem, { timeout: 30000 });
  assert.match(await page.locator('#surface-info').textContent(), /87×61 grid · 5307 points/);
  const loaded = await page.locator('#load-message').textContent();
  assert.match(loaded, /pixel size 10 × 10 map units/, loaded);
  assert.match(loaded, /map \(2667400, 6478710\)/, loaded);
  assert.match(loaded, /nodata -9999: 14 cells filled/, loaded);
  const source = await page.locator('#surface-source').textContent();
  assert.match(source, /GeoTIFF .*14 nodata cells/);
  // The page's surface kept the georeferencing the Worker read, not only its summary.
  assert.match(source, /georeferencing: pixel size 10 × 10 map units · pixel \(0, 0\) corner at map \(2667400, 6478710\)/, source);

  // 2. Run to the end: the knee is selected and drawn.
  await page.selectOption('#algorithm', 'nsga2');
  await page.fill('#population', '16');
  await page.fill('#generations', '4');
  await page.click('#run');
  await page.waitForFunction(() => /done/.test(document.getElementById('status').textContent), null, { timeout: 60000 });
  await page.waitForFunction(() => window.paretomesh.selectedVertexCount() !== undefined, null, { timeout: 10000 });
  const [index, t] = await page.evaluate(() => window.paretomesh.selectedObjectives());
  assert.ok(index >= 0, 'a front member is selected');
  assert.match(await page.locator('#selection-info').textContent(), new RegExp(`T = ${t} triangles`));
  await page.waitForTimeout(300);
  const view = await page.locator('#view').screenshot({ path: path.join(shots, 'import-01-geotiff-selected.png') });
  assert.ok((await pixelVariance(page, view)) > 50, 'the selected mesh is drawn');

  // The exported mesh lies on the map as `paretomesh export` puts it: 10 m sample centres from
  // the tie point's pixel corner (2667400, 6478710) plus half a pixel, rows turned so that y
  // grows northwards; the four corners are always kept, so they span the DEM exactly.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-ply')]);
  const ply = readFileSync(await download.path(), 'utf8');
  const header = ply.slice(0, ply.indexOf('end_header\n'));
  const nv = Number(/element vertex (\d+)/.exec(header)[1]);
  assert.equal(nv, await page.evaluate(() => window.paretomesh.selectedVertexCount()), 'the selected mesh is exported');
  const vertices = ply.slice(header.length + 'end_header\n'.length).trim().split('\n').slice(0, nv).map((l) => l.split(' ').map(Number));
  const xs = vertices.map((v) => v[0]);
  const ys = vertices.map((v) => v[1]);
  assert.deepEqual([Math.min(...xs), Math.max(...xs)], [2667405, 2667405 + 86 * 10], 'x spans the DEM in map units');
  assert.deepEqual([Math.min(...ys), Math.max(...ys)], [6478705 - 60 * 10, 6478705], 'y spans the DEM in map units');
  for (const [x, y, z] of vertices) {
    assert.ok(Number.isInteger((x - 2667405) / 10) && Number.isInteger((y - 6478105) / 10), `a sample centre: ${x} ${y}`);
    assert.ok(z >= 90 && z <= 200, `a height of the volcano: ${z}`);
  }

  // 3. A GeoTIFF of 2100×2050 (4.3 M points, within the tab's cap): it opens at its native
  // size, never resampled behind the user's back, with its nodata cell filled.
  const big = int16GeoTiff(2100, 2050, (x, y) => (x === 5 && y === 7 ? -32768 : Math.round(100 * Math.sin(x / 50) + 80 * Math.cos(y / 70))));
  await dropFiles(page, [{ name: 'big_dem.tif', bytes: big }]);
  await page.waitForFunction(() => window.paretomesh.surfaceName() === 'big_dem.tif', null, { timeout: 60000 });
  assert.match(await page.locator('#surface-info').textContent(), /2100×2050 grid · 4305000 points/);
  assert.equal(await page.locator('#import-dialog[open]').count(), 0, 'no dialog for a GeoTIFF the tab can hold');
  const georeference = await page.locator('#surface-source').textContent();
  await page.screenshot({ path: path.join(shots, 'import-02-geotiff-native.png') });

  // 4. A closed, thick mesh folds in every projection: the dialog offers its outer surface.
  await dropFiles(page, [{ name: 'tube.obj', bytes: Buffer.from(thickTubeObj()) }]);
  await page.waitForSelector('#import-dialog[open]', { timeout: 30000 });
  assert.match(await page.locator('#import-title').textContent(), /folds/);
  assert.equal(await page.inputValue('#import-surface'), 'outer');
  const folds = await page.locator('#import-folds').textContent();
  assert.match(folds, /cylindrical: \d+ % of the covered grid is covered more than once/, folds);
  assert.match(await page.locator('#import-summary').textContent(), /outer surface: \d+ grid points .* covered more than once and took the outermost hit/);
  await page.screenshot({ path: path.join(shots, 'import-03-folding-mesh.png') });
  // The single surface is refused in the dialog with the reason; the outer one loads.
  await page.selectOption('#import-surface', 'single');
  await page.click('#import-apply');
  await page.waitForFunction(() => /folds over itself/.test(document.getElementById('import-message').textContent), null, { timeout: 30000 });
  await page.selectOption('#import-surface', 'outer');
  await page.click('#import-use');
  await page.waitForFunction(() => window.paretomesh.surfaceName() === 'tube.obj', null, { timeout: 30000 });
  assert.match(await page.locator('#surface-source').textContent(), /cylindrical unwrap.*outer surface/);

  assert.deepEqual(realErrors(page), [], 'no page errors');
  console.log(`import e2e ok: ${dem} selected T = ${t}; ${georeference}; ${folds}`);
});
