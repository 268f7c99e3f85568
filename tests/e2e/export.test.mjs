// End-to-end test of where a mesh leaves the app, in headless Chromium: a finished run selects
// the knee of its front, the Trade-off and Knee buttons switch between the two picks, the E
// axis shows sum, mean or max and hovering a member reads out all three, "printable solid"
// exports a closed, outward-facing STL, 3MF downloads as a zip package of the same solid, the
// front downloads as a 3D Tiles pyramid in a zip whose tileset's every tile is in it, and
// ticking the teaching view switches the method to
// NSGA-II in one action.
import { readFileSync } from 'node:fs';
import { inflateRawSync } from 'node:zlib';
import path from 'node:path';
import assert from 'node:assert/strict';
import { shots, withApp, newPage, realErrors, waitForApp, tradeOffCandidates, kneeIndex } from './harness.mjs';

/// The entries of a zip archive by name, inflated into Buffers, read through its central directory.
function unzip(zip) {
  const end = zip.lastIndexOf(Buffer.from([0x50, 0x4b, 0x05, 0x06]));
  assert.ok(end >= 0, 'a zip archive ends with its directory record');
  const entries = zip.readUInt16LE(end + 10);
  let at = zip.readUInt32LE(end + 16);
  const out = {};
  for (let k = 0; k < entries; k++) {
    assert.equal(zip.readUInt32LE(at), 0x02014b50);
    const method = zip.readUInt16LE(at + 10);
    const packed = zip.readUInt32LE(at + 20);
    const nameLength = zip.readUInt16LE(at + 28);
    const skip = nameLength + zip.readUInt16LE(at + 30) + zip.readUInt16LE(at + 32);
    const local = zip.readUInt32LE(at + 42);
    const name = zip.toString('utf8', at + 46, at + 46 + nameLength);
    const start = local + 30 + zip.readUInt16LE(local + 26) + zip.readUInt16LE(local + 28);
    const data = zip.subarray(start, start + packed);
    out[name] = method === 8 ? inflateRawSync(data) : data;
    at += 46 + skip;
  }
  return out;
}

const pairs = (flat) => Array.from({ length: flat.length / 2 }, (_, i) => [flat[2 * i], flat[2 * i + 1]]);

await withApp(async ({ browser, url }) => {
  const page = await newPage(browser);
  await page.goto(url);
  await waitForApp(page);

  // 1. A small NSGA-II run on the built-in surface ends with its knee selected.
  await page.selectOption('#algorithm', 'nsga2');
  await page.fill('#population', '16');
  await page.fill('#generations', '6');
  await page.click('#run');
  await page.waitForFunction(() => /done/.test(document.getElementById('status').textContent), null, { timeout: 60000 });
  await page.waitForFunction(() => window.paretomesh.selectedVertexCount() !== undefined, null, { timeout: 10000 });
  const front = pairs(await page.evaluate(() => window.paretomesh.frontObjectives()));
  assert.ok(front.length >= 5, `a front of ${front.length} members`);
  const knee = kneeIndex(front);
  const selected = async () => (await page.evaluate(() => window.paretomesh.selectedObjectives()))[0];
  assert.equal(await selected(), knee, 'the run ends on the knee');
  assert.ok(knee > 0 && knee < front.length - 1, `the knee is a middle member (${knee} of ${front.length})`);

  // 2. The paper's trade-off pick is one click away, and so is the knee again.
  await page.click('#select-tradeoff');
  const tradeOff = await selected();
  assert.ok(tradeOffCandidates(front).has(tradeOff), `the trade-off pick (${tradeOff})`);
  await page.click('#select-knee');
  assert.equal(await selected(), knee);

  // 3. The E axis as sum, mean or max; hovering a member reads out all three in the surface's
  // units (metres for the built-in DEM).
  const positions = {};
  for (const mode of ['sum', 'mean', 'max']) {
    await page.selectOption('#plot-e-axis', mode);
    await page.waitForTimeout(200);
    positions[mode] = await page.evaluate(() => window.paretomesh.frontPointPosition(1));
    await page.locator('#plot').screenshot({ path: path.join(shots, `export-plot-${mode}.png`) });
  }
  // Mean is sum scaled by 1/N: on a linear or log axis fitted to the data the points sit alike.
  assert.ok(Math.abs(positions.sum[1] - positions.mean[1]) < 1.5, `${positions.sum} vs ${positions.mean}`);
  assert.notDeepEqual(positions.sum, positions.max, 'E_max moves the points');
  const box = await page.locator('#plot').boundingBox();
  const [x, y] = positions.max;
  await page.mouse.move(box.x + x, box.y + y);
  await page.waitForFunction(() => window.paretomesh.hoveredText() !== undefined, null, { timeout: 5000 });
  const hover = await page.evaluate(() => window.paretomesh.hoveredText());
  assert.match(hover, new RegExp(`^T = ${front[1][0]} · E_sum = \\S+ · mean = \\S+ m · E_max = \\S+ m$`), hover);
  await page.selectOption('#plot-e-axis', 'sum');

  // 4. A printable solid: closed (every edge used once each way round by the welded corners)
  // and facing outwards (positive volume).
  await page.check('#export-solid');
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-stl')]);
  assert.match(download.suggestedFilename(), /_solid\.stl$/);
  const stl = readFileSync(await download.path());
  const count = stl.readUInt32LE(80);
  assert.equal(stl.length, 84 + 50 * count);
  const ids = new Map();
  const id = (o) => {
    const key = [0, 4, 8].map((k) => stl.readUInt32LE(o + k)).join(',');
    if (!ids.has(key)) ids.set(key, [stl.readFloatLE(o), stl.readFloatLE(o + 4), stl.readFloatLE(o + 8)]);
    return key;
  };
  const edges = new Map();
  let volume = 0;
  for (let f = 0; f < count; f++) {
    const o = 84 + 50 * f + 12;
    const v = [id(o), id(o + 12), id(o + 24)];
    for (let k = 0; k < 3; k++) {
      const e = `${v[k]}|${v[(k + 1) % 3]}`;
      edges.set(e, (edges.get(e) ?? 0) + 1);
    }
    const [a, b, c] = v.map((key) => ids.get(key));
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
  }
  for (const [e, n] of edges) {
    const [p, q] = e.split('|');
    assert.equal(n, 1, `edge ${e} used ${n} times`);
    assert.equal(edges.get(`${q}|${p}`), 1, `edge ${e} has no opposite`);
  }
  assert.ok(volume > 0, `volume ${volume}`);
  const [tSelected] = front[knee];
  assert.ok(count > tSelected, `${count} faces: the surface's ${tSelected} and the walls and bottom`);
  await page.uncheck('#export-solid');

  // 4b. 3MF is always the solid: a zip package whose model part holds the STL's faces.
  const [package3mf] = await Promise.all([page.waitForEvent('download'), page.click('#export-3mf')]);
  assert.match(package3mf.suggestedFilename(), /_solid\.3mf$/);
  const zip = readFileSync(await package3mf.path());
  const parts = unzip(zip);
  assert.deepEqual(Object.keys(parts).sort(), ['3D/3dmodel.model', '[Content_Types].xml', '_rels/.rels']);
  const model = parts['3D/3dmodel.model'].toString('utf8');
  assert.match(model, /^<\?xml[^>]*>\s*<model unit="millimeter"/);
  const modelTriangles = (model.match(/<triangle /g) ?? []).length;
  const modelVertices = (model.match(/<vertex /g) ?? []).length;
  assert.equal(modelTriangles, count, 'the 3MF holds the solid STL\'s faces');
  assert.equal(modelVertices, ids.size, 'and its welded corners');

  // 4c. The front as a 3D Tiles pyramid: tileset.json and every tile it names, each a glb.
  const [pyramid] = await Promise.all([page.waitForEvent('download'), page.click('#export-tiles')]);
  assert.match(pyramid.suggestedFilename(), /_3dtiles\.zip$/);
  assert.equal(await page.locator('#export-message').textContent(), '', 'no refusal');
  const tiles = unzip(readFileSync(await pyramid.path()));
  assert.ok(tiles['tileset.json'], 'the zip holds tileset.json');
  const tileset = JSON.parse(tiles['tileset.json'].toString('utf8'));
  assert.equal(tileset.asset.version, '1.1');
  const uris = [];
  const walk = (node) => {
    if (node.content) uris.push(node.content.uri);
    (node.children ?? []).forEach(walk);
  };
  walk(tileset.root);
  assert.ok(uris.length >= 5, `${uris.length} tiles: at least two levels`);
  for (const uri of uris) {
    assert.ok(tiles[uri], `${uri} is in the zip`);
    assert.equal(tiles[uri].toString('latin1', 0, 4), 'glTF', `${uri} is a glb`);
  }
  assert.equal(Object.keys(tiles).length, uris.length + 1, 'the tileset and its tiles, nothing else');

  // 5. The teaching view from the default method: one tick switches to NSGA-II.
  await page.click('#reset');
  await page.selectOption('#algorithm', 'memetic');
  await page.check('#teach');
  await page.waitForSelector('#teaching', { state: 'visible', timeout: 5000 });
  assert.equal(await page.locator('#algorithm').inputValue(), 'nsga2');
  assert.equal(await page.locator('#teach-phase').isDisabled(), false);
  await page.click('#teach-phase');
  await page.waitForFunction(() => (window.paretomesh.teachingState() ?? [])[0] === 'selection', null, { timeout: 60000 });

  assert.deepEqual(realErrors(page), [], 'no page errors');
  console.log(`export e2e: knee ${knee}, trade-off ${tradeOff} of ${front.length}; solid STL of ${count} faces, volume ${volume.toFixed(0)}; 3MF of ${zip.length} bytes; 3D Tiles zip of ${uris.length} tiles`);
});
