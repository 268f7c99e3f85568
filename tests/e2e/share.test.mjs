// End-to-end test of share links in headless Chromium:
// 1. the quick curated example (bunny, NSGA-II 40 × 20, seed 7) opened as a link re-runs to the
//    same front and the same selected solution as the CLI with the same settings (E and T
//    compared exactly), and sharing it again gives the identical link;
// 2. malformed and hostile links show a clear message, keep the default demo, and never panic;
// 3. a run on a dropped file shared by fingerprint asks for the file, refuses a wrong one and
//    reproduces with the right one; the same run shared with the grid embedded reproduces with
//    no file at all;
// 4. a mesh's link carries its import choice;
// 5. a GeoTIFF DEM's embedded-grid link reopens on the same map: same georeferencing, same
//    front, and a PLY export with the same vertex coordinates.
// Needs the CLI (cargo build --bin paretomesh; `cargo test` builds it too) and www/pkg. The
// debug build: its numbers are the same bits as the release build's (no fast-math anywhere),
// and it saves CI a release build of its own.
import { readFileSync } from 'node:fs';
import path from 'node:path';
import assert from 'node:assert/strict';
import { root, shots, withApp, newPage, realErrors, waitForApp, dropFiles, wavyObj, kneeIndex, int16GeoTiff } from './harness.mjs';
import { cliFront } from './cli.mjs';


const pairs = (flat) => flat.reduce((acc, v, i) => (i % 2 ? acc[acc.length - 1].push(v) : acc.push([v]), acc), []);

// Waits until the page is done re-running a link (up to `timeout` ms).
async function waitForReproduction(page, timeout = 180000) {
  await page.waitForFunction(() => window.paretomesh && !window.paretomesh.isReproducing() && window.paretomesh.generation() > 0, null, { timeout });
}

async function openLink(browser, url, fragment) {
  const page = await newPage(browser);
  await page.goto(`${url}#${fragment}`);
  await waitForApp(page);
  return page;
}

async function shareNow(page, { embed = false } = {}) {
  if (embed) await page.check('#share-embed');
  await page.click('#share');
  const shared = await page.inputValue('#share-url');
  assert.ok(shared.includes('#v1.'), `a share link was produced: ${shared}`);
  return shared.slice(shared.indexOf('#') + 1);
}

// Runs NSGA-II with population 20 on the page's surface to the end; returns its front.
async function runSmall(page, { generations, seed }) {
  await page.selectOption('#algorithm', 'nsga2');
  await page.fill('#population', '20');
  await page.fill('#generations', String(generations));
  await page.fill('#seed', String(seed));
  await page.click('#run');
  await page.waitForFunction(() => /done/.test(document.getElementById('status').textContent), null, { timeout: 60000 });
  return page.evaluate(() => window.paretomesh.frontObjectives());
}

await withApp(async ({ browser, url }) => {
  // 1. The quick curated example against the CLI.
  const home = await newPage(browser);
  await home.goto(url);
  await waitForApp(home);
  const examples = await home.$$eval('#examples a', (as) => as.map((a) => ({ title: a.textContent, hash: a.hash.slice(1) })));
  assert.ok(examples.length >= 3, `the page lists curated examples (${examples.length})`);
  const quick = examples.find((e) => /Range scan/.test(e.title));
  assert.ok(quick, 'the range-scan example is listed');
  await home.close();

  const started = Date.now();
  const page = await openLink(browser, url, quick.hash);
  assert.equal(await page.evaluate(() => window.paretomesh.surfaceName()), 'bunny_65x65');
  await waitForReproduction(page);
  const seconds = (Date.now() - started) / 1000;
  const browserFront = pairs(await page.evaluate(() => window.paretomesh.frontObjectives()));
  const expected = cliFront(['tests/data/bunny_65x65.f32', '--algo', 'nsga2', '--pop', '40', '--gens', '20', '--seed', '7']);
  assert.equal(await page.evaluate(() => window.paretomesh.generation()), 20);
  assert.deepEqual(browserFront, expected, 'the link reproduces the CLI front exactly (T and E)');
  const [index, t, e] = await page.evaluate(() => window.paretomesh.selectedObjectives());
  // The run ended at its last generation: the link's own selection wins over the knee.
  assert.equal(index, 30, 'the link selects front member 30');
  assert.deepEqual([t, e], expected[30], 'the selected solution is the CLI front member 30');
  assert.ok(await page.isChecked('#show-original'), 'the link turned the original-surface toggle on');
  assert.ok(!(await page.isChecked('#show-error')), 'and left the error map off');
  assert.equal(await shareNow(page), quick.hash, 'sharing the reproduced view gives the same link');
  await page.screenshot({ path: path.join(shots, 'share-01-example.png') });
  assert.deepEqual(realErrors(page), [], 'no page errors');
  await page.close();

  // 2. Malformed and hostile links.
  const settings = (obj) => Buffer.from(JSON.stringify(obj)).toString('base64url');
  const good = JSON.parse(Buffer.from(quick.hash.split('.')[1], 'base64url').toString());
  const hostile = {
    'not base64': 'v1.@@@###',
    'unknown version': 'v9.e30',
    'cut short': quick.hash.slice(0, quick.hash.length - 7),
    'wrong type': `v1.${settings({ ...good, generations_run: 'many' })}`,
    'huge number': `v1.${settings({ ...good, params: { ...good.params, population: 1e12 } })}`,
    'unknown surface': `v1.${settings({ ...good, surface: { kind: 'builtin', name: '../../etc/passwd' } })}`,
    'corrupt grid': `v1.${settings({ ...good, surface: { kind: 'embedded', name: 'x', width: 65, height: 65 } })}.AAAAAAAA`,
    'oversized': `v1.${'A'.repeat(40000)}`,
  };
  const messages = {};
  for (const [what, fragment] of Object.entries(hostile)) {
    const p = await openLink(browser, url, fragment);
    await p.waitForFunction(() => document.querySelector('#load-message.error') !== null, null, { timeout: 10000 });
    messages[what] = await p.locator('#load-message').textContent();
    assert.match(messages[what], /cannot be opened/, `${what}: a clear message`);
    assert.match(messages[what], /default demo/, `${what}: says the default demo is shown`);
    assert.equal(await p.evaluate(() => window.paretomesh.surfaceName()), 'jacksboro_65x65', `${what}: default demo`);
    assert.ok(await p.locator('#panic').isHidden(), `${what}: no panic`);
    assert.deepEqual(realErrors(p), [], `${what}: no page errors`);
    await p.close();
  }

  // 3. A dropped file, shared by fingerprint and embedded.
  // A .f32 grid with its sidecar: f32 heights embed exactly (a text PLY's would be rounded).
  const dropped = [
    { name: 'bunny_33x33.f32', bytes: readFileSync(path.join(root, 'tests/data/bunny_33x33.f32')) },
    { name: 'bunny_33x33.json', bytes: readFileSync(path.join(root, 'tests/data/bunny_33x33.json')) },
  ];
  const wrong = { name: 'volcano_87x61.ply', bytes: readFileSync(path.join(root, 'tests/data/volcano_87x61.ply')) };
  const author = await newPage(browser);
  await author.goto(url);
  await waitForApp(author);
  await dropFiles(author, dropped);
  await author.waitForFunction(() => window.paretomesh.surfaceName() === 'bunny_33x33.f32', null, { timeout: 30000 });
  const authorFront = await runSmall(author, { generations: 5, seed: 11 });
  // The finished run selected the knee of its front and shows it in 3-D.
  await author.waitForFunction(() => window.paretomesh.selectedVertexCount() !== undefined, null, { timeout: 10000 });
  const [autoIndex, autoT, autoE] = await author.evaluate(() => window.paretomesh.selectedObjectives());
  assert.equal(autoIndex, kneeIndex(pairs(authorFront)), "the run's end selects the knee");
  assert.deepEqual([autoT, autoE], pairs(authorFront)[autoIndex]);
  assert.match(await author.locator('#selection-info').textContent(), new RegExp(`T = ${autoT} triangles`));
  const [x, y] = await author.evaluate(() => window.paretomesh.frontPointPosition(3));
  const box = await author.locator('#plot').boundingBox();
  await author.mouse.click(box.x + x, box.y + y);
  const authorSelected = await author.evaluate(() => window.paretomesh.selectedObjectives());
  assert.ok(authorSelected && authorSelected[0] >= 0, 'a front member is selected');
  const byFingerprint = await shareNow(author);
  const embedded = await shareNow(author, { embed: true });
  assert.ok(embedded.split('.').length === 3, 'the embedded link carries a grid part');
  assert.deepEqual(realErrors(author), [], 'no page errors while sharing');
  await author.close();

  const reader = await openLink(browser, url, byFingerprint);
  assert.match(await reader.locator('#load-message').textContent(), /bunny_33x33\.f32 .*Drop that file/);
  await dropFiles(reader, [wrong]);
  await reader.waitForFunction(() => document.querySelector('#load-message.error') !== null, null, { timeout: 30000 });
  assert.match(await reader.locator('#load-message').textContent(), /not the file the share link expects/);
  assert.equal(await reader.evaluate(() => window.paretomesh.surfaceName()), 'jacksboro_65x65', 'the wrong file is refused');
  await dropFiles(reader, dropped);
  await waitForReproduction(reader);
  assert.equal(await reader.evaluate(() => window.paretomesh.surfaceName()), 'bunny_33x33.f32');
  assert.deepEqual(await reader.evaluate(() => window.paretomesh.frontObjectives()), authorFront, 'fingerprint link: same front');
  assert.deepEqual(await reader.evaluate(() => window.paretomesh.selectedObjectives()), authorSelected, 'fingerprint link: same selection');
  await reader.close();

  const embeddedReader = await openLink(browser, url, embedded);
  await waitForReproduction(embeddedReader);
  assert.deepEqual(await embeddedReader.evaluate(() => window.paretomesh.frontObjectives()), authorFront, 'embedded link: same front');
  assert.deepEqual(await embeddedReader.evaluate(() => window.paretomesh.selectedObjectives()), authorSelected, 'embedded link: same selection');
  await embeddedReader.screenshot({ path: path.join(shots, 'share-02-embedded.png') });
  assert.deepEqual(realErrors(embeddedReader), [], 'no page errors');
  await embeddedReader.close();

  // 4. A mesh that is not a grid: the link carries the import dialog's choice (projection and
  // grid size), so the reader who drops the same file gets the same grid without the dialog.
  const mesh = [{ name: 'wavy.obj', bytes: Buffer.from(wavyObj(30, 20)) }];
  const meshAuthor = await newPage(browser);
  await meshAuthor.goto(url);
  await waitForApp(meshAuthor);
  await dropFiles(meshAuthor, mesh);
  await meshAuthor.waitForSelector('#import-dialog[open]', { timeout: 10000 });
  await meshAuthor.selectOption('#import-projection', 'planar');
  await meshAuthor.fill('#import-width', '36');
  await meshAuthor.fill('#import-height', '22');
  await meshAuthor.click('#import-use');
  await meshAuthor.waitForFunction(() => window.paretomesh.surfaceName() === 'wavy.obj', null, { timeout: 10000 });
  const meshInfo = await meshAuthor.locator('#surface-info').textContent();
  assert.match(meshInfo, /36×22 grid/);
  const meshFront = await runSmall(meshAuthor, { generations: 4, seed: 5 });
  const meshLink = await shareNow(meshAuthor);
  assert.deepEqual(realErrors(meshAuthor), [], 'no page errors while sharing a mesh');
  await meshAuthor.close();
  const meshReader = await openLink(browser, url, meshLink);
  // The same file gridded another way (here the page's no-Worker path, which takes the
  // defaults) is refused, with both choices named.
  const refused = await meshReader.evaluate((text) => window.paretomesh.loadFile('wavy.obj', new TextEncoder().encode(text)), wavyObj(30, 20));
  assert.equal(refused, false, 'a different gridding is refused');
  assert.match(await meshReader.locator('#load-message').textContent(), /right file, but the share link turned it into a grid with the planar projection on a 36×22 grid and this load used the auto projection/);
  await dropFiles(meshReader, mesh);
  await waitForReproduction(meshReader);
  assert.equal(await meshReader.evaluate(() => document.getElementById('import-dialog').open), false, 'no import dialog: the link says how');
  assert.equal(await meshReader.locator('#surface-info').textContent(), meshInfo, 'the same grid');
  assert.deepEqual(await meshReader.evaluate(() => window.paretomesh.frontObjectives()), meshFront, 'mesh link: same front');
  assert.deepEqual(realErrors(meshReader), [], 'no page errors');
  await meshReader.close();

  // 5. A GeoTIFF DEM shared with its grid embedded: the reader's surface lies on the same map
  // (spacing, origin, georeference, filled nodata cells), so its export has the same vertices.
  const dem = [{ name: 'dem.tif', bytes: int16GeoTiff(40, 30, (x, y) => (x === 3 && y === 4 ? -32768 : Math.round(50 * Math.sin(x / 6) + 30 * Math.cos(y / 5) + x)), { scale: [30, 25, 0], tie: [0, 0, 0, 500000, 4000000, 0] }) }];
  const exportPly = async (p) => {
    const [download] = await Promise.all([p.waitForEvent('download'), p.click('#export-ply')]);
    const ply = readFileSync(await download.path(), 'utf8');
    const nv = Number(/element vertex (\d+)/.exec(ply)[1]);
    return ply.slice(ply.indexOf('end_header\n') + 'end_header\n'.length).trim().split('\n').slice(0, nv);
  };
  const demAuthor = await newPage(browser);
  await demAuthor.goto(url);
  await waitForApp(demAuthor);
  await dropFiles(demAuthor, dem);
  await demAuthor.waitForFunction(() => window.paretomesh.surfaceName() === 'dem.tif', null, { timeout: 30000 });
  const demSource = await demAuthor.locator('#surface-source').textContent();
  assert.match(demSource, /georeferencing: pixel size 30 × 25 map units .*nodata -32768: 1 cells filled/);
  const demFront = await runSmall(demAuthor, { generations: 3, seed: 9 });
  const authorVertices = await exportPly(demAuthor);
  // Grid point (0, 0) is the south-west pixel centre: x = 500000 + 15, y = 4000000 − 29.5 · 25.
  assert.ok(authorVertices.some((v) => v.startsWith('500015 3999262.5 ')), `map coordinates: ${authorVertices[0]}`);
  const demLink = await shareNow(demAuthor, { embed: true });
  assert.deepEqual(realErrors(demAuthor), [], 'no page errors while sharing a DEM');
  await demAuthor.close();
  const demReader = await openLink(browser, url, demLink);
  await waitForReproduction(demReader);
  const readerSource = await demReader.locator('#surface-source').textContent();
  assert.equal(readerSource.split(' · georeferencing: ')[1], demSource.split(' · georeferencing: ')[1], 'the same georeferencing');
  assert.deepEqual(await demReader.evaluate(() => window.paretomesh.frontObjectives()), demFront, 'DEM link: same front');
  assert.deepEqual(await exportPly(demReader), authorVertices, 'DEM link: the export lands on the same map coordinates');
  assert.deepEqual(realErrors(demReader), [], 'no page errors');
  await demReader.close();

  console.log(`share e2e ok: the bunny example re-ran to the CLI's front of ${expected.length} members in ${seconds.toFixed(1)} s; ` +
    `link lengths: example ${quick.hash.length}, file ${byFingerprint.length}, embedded 33×33 ${embedded.length}, embedded 40×30 DEM ${demLink.length} characters; ` +
    `hostile-link message example: ${messages['huge number']}`);
});
