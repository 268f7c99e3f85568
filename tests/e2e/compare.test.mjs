// End-to-end test of compare mode in headless Chromium (playwright-core driving
// /usr/bin/chromium). Serves the built app (www/pkg must exist: scripts/build-web.sh), then on
// the built-in surface: small GA settings → turn compare mode on → Compare → the table is live
// while the methods run → all five finish with non-empty fronts → the tables list the five
// methods, their picks and all 20 ordered pairs with finite numbers equal to the app's own
// table → a click on a front point and one on a pick show those meshes → compare mode off
// brings the single-run plot back. Screenshots go to target/e2e/. Prints (does not assert) the
// frame timing, the share of wall time spent optimising, and the comparison's run time.
import path from 'node:path';
import assert from 'node:assert/strict';
import { shots, withApp, newPage, realErrors, waitForApp } from './harness.mjs';

// GA settings of the comparison: small enough for a test (the weighted-sum GA runs 11 GAs).
// COMPARE_POP / COMPARE_GENS override them, e.g. 100 / 50 for the paper's settings.
const POPULATION = process.env.COMPARE_POP ?? '20';
const GENERATIONS = process.env.COMPARE_GENS ?? '8';
const SEED = '3';
// How long the comparison may take; raise it with the paper's settings (COMPARE_TIMEOUT_S).
const TIMEOUT_MS = 1000 * Number(process.env.COMPARE_TIMEOUT_S ?? '600');
const METHODS = ['nsga2', 'weighted', 'decimation', 'greedy', 'memetic'];

// The numbers of a table body: one array of cells per row, each cell's data-value (the full
// precision the page was given) parsed as a number.
const cellValues = (page, id) => page.$$eval(`#${id} tr`, (rows) => rows.map((r) => ({
  method: r.dataset.method, a: r.dataset.a, b: r.dataset.b,
  values: [...r.querySelectorAll('td[data-value]')].map((td) => (td.dataset.value === '' ? NaN : Number(td.dataset.value))),
  picks: [...r.querySelectorAll('td[data-pick]')].map((td) => ({ kind: td.dataset.pick, e: Number(td.dataset.e), t: Number(td.dataset.t) })),
})));

await withApp(async ({ browser, url }) => {
  const page = await newPage(browser);
  // Tall enough that the panel's three tables are in the screenshots.
  await page.setViewportSize({ width: 1400, height: 1300 });
  await page.goto(url);
  await waitForApp(page);
  assert.match(await page.locator('#surface-info').textContent(), /jacksboro_65x65 · 65×65 grid/);

  // 1. The form's GA parameters, then compare mode on: its panel replaces the single-run plot.
  // The GA fields show once a GA is chosen (the default, memetic, runs with its own parameters).
  await page.selectOption('#algorithm', 'nsga2');
  await page.fill('#population', POPULATION);
  await page.fill('#generations', GENERATIONS);
  await page.fill('#seed', SEED);
  assert.ok(await page.locator('#plot').isVisible(), 'the single-run plot shows before compare mode');
  await page.check('#compare-on');
  assert.ok(await page.locator('#compare-plot').isVisible(), 'compare mode shows its plot');
  assert.ok(!(await page.locator('#plot').isVisible()), 'the single-run plot steps aside');
  assert.ok(await page.locator('#export-ply').isVisible(), 'the exports stay');

  // 2. Compare, measuring frame intervals and watching the table while the methods run.
  await page.evaluate(() => {
    window.__frames = [];
    window.__liveTables = new Set();
    let last = performance.now();
    const tick = (t) => {
      window.__frames.push(t - last);
      last = t;
      // Distinct tables shown before the comparison was done.
      const table = window.paretomesh.compareTable();
      if (table && !window.paretomesh.compareDone() && !JSON.parse(table).complete) window.__liveTables.add(table);
      if (!window.__stopFrames) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
  const started = Date.now();
  await page.click('#compare-run');
  await page.waitForTimeout(1500);
  await page.screenshot({ path: path.join(shots, 'compare-01-running.png') });
  await page.waitForFunction(
    () => window.paretomesh.compareDone() || document.getElementById('compare-message').textContent !== '',
    null, { timeout: TIMEOUT_MS, polling: 1000 });
  const wallMs = Date.now() - started;
  assert.equal(await page.locator('#compare-message').textContent(), '', 'the comparison runs');
  await page.waitForTimeout(400); // the final table and a few more frames
  const { frames, liveTables } = await page.evaluate(() => {
    window.__stopFrames = true;
    return { frames: window.__frames, liveTables: window.__liveTables.size };
  });
  assert.ok(liveTables >= 2, `the table changed while the methods ran (${liveTables} live tables)`);
  const [evaluations, optimisingMs] = await page.evaluate(() => window.paretomesh.compareTotals());

  // 3. Five non-empty fronts.
  const lengths = await page.evaluate(() => window.paretomesh.compareFrontLengths());
  assert.equal(lengths.length, METHODS.length);
  assert.ok(lengths.every((n) => n > 0), `five non-empty fronts: ${lengths}`);
  assert.ok(lengths[1] <= 11, 'the weighted-sum GA has at most one point per weight');
  assert.match(await page.locator('#compare-status').textContent(), /^done · /);

  // 4. The tables: the five methods, their picks, all 20 ordered pairs, finite numbers equal
  // to the app's table, final.
  const table = JSON.parse(await page.evaluate(() => window.paretomesh.compareTable()));
  assert.ok(table.complete, 'the table is final');
  assert.equal(table.methods.reduce((sum, m) => sum + m.evaluations, 0), evaluations, 'the evaluations add up');
  const methods = await cellValues(page, 'compare-methods');
  assert.deepEqual(methods.map((r) => r.method), METHODS);
  methods.forEach((r, k) => {
    assert.equal(r.values.length, 1, 'one HVR per method');
    const hvr = r.values[0];
    assert.ok(Number.isFinite(hvr) && hvr > 0 && hvr <= 1, `${r.method} HVR ${hvr}`);
    assert.equal(hvr, table.methods[k].hvr);
    assert.equal(table.methods[k].front_size, lengths[k]);
  });
  const picks = await cellValues(page, 'compare-picks');
  assert.deepEqual(picks.map((r) => r.method), METHODS);
  picks.forEach((r, k) => {
    assert.deepEqual(r.picks.map((p) => p.kind), ['best error', 'fewest triangles', 'trade-off']);
    const expected = table.methods[k].picks;
    for (const [p, key] of r.picks.map((p, i) => [p, ['best_error', 'fewest_triangles', 'trade_off'][i]])) {
      assert.ok(Number.isFinite(p.e) && p.e >= 0 && Number.isInteger(p.t) && p.t >= 2, `${r.method} ${p.kind}`);
      assert.deepEqual({ e: p.e, t: p.t }, expected[key]);
    }
    // Best error has the lowest E and fewest triangles the lowest T of the three.
    assert.ok(r.picks[0].e <= r.picks[1].e && r.picks[0].e <= r.picks[2].e, `${r.method} best error`);
    assert.ok(r.picks[1].t <= r.picks[0].t && r.picks[1].t <= r.picks[2].t, `${r.method} fewest triangles`);
  });
  const pairs = await cellValues(page, 'compare-pairs');
  assert.equal(pairs.length, METHODS.length * (METHODS.length - 1), 'every ordered pair');
  const expectedPairs = METHODS.flatMap((a) => METHODS.filter((b) => b !== a).map((b) => `${a}>${b}`));
  assert.deepEqual(pairs.map((r) => `${r.a}>${r.b}`), expectedPairs);
  pairs.forEach((r, i) => {
    const [eps, c] = r.values;
    assert.ok(Number.isFinite(eps) && Number.isFinite(c) && c >= 0 && c <= 1, `${r.a} vs ${r.b}: ${r.values}`);
    assert.equal(eps, table.pairs[i].epsilon);
    assert.equal(c, table.pairs[i].coverage);
  });
  const note = await page.locator('#compare-note').textContent();
  assert.match(note, /E ÷ .* \(E of the corner-only mesh\), T ÷ 8192/);
  assert.match(note, /reference point \(1\.1, 1\.1\)/);
  assert.match(note, /Final/);
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(shots, 'compare-02-done.png') });
  await page.locator('#compare').screenshot({ path: path.join(shots, 'compare-03-panel.png') });

  // The finished comparison selected the trade-off pick of the merged fronts: a mesh in the
  // 3-D view that none of the table's picks (all front members) dominates.
  const auto = await page.evaluate(() => window.paretomesh.selectedObjectives());
  assert.ok(auto, 'the end of the comparison selects a mesh');
  const [, autoT, autoE] = auto;
  assert.ok((await page.evaluate(() => window.paretomesh.selectedVertexCount())) >= 4, 'and shows it');
  assert.match(await page.locator('#selection-info').textContent(), new RegExp(`T = ${autoT} triangles`));
  for (const p of picks.flatMap((r) => r.picks)) {
    assert.ok(!(p.t <= autoT && p.e <= autoE && (p.t < autoT || p.e < autoE)), `the ${p.kind} pick (${p.t}, ${p.e}) does not dominate the selection (${autoT}, ${autoE})`);
  }

  // 5. A click on a point of NSGA-II's front shows that mesh; so does a click on a pick.
  const pick = Math.floor(lengths[0] / 2);
  const [x, y] = await page.evaluate((i) => window.paretomesh.comparePointPosition(0, i), pick);
  const box = await page.locator('#compare-plot').boundingBox();
  await page.mouse.click(box.x + x, box.y + y);
  await page.waitForFunction(() => window.paretomesh.selectedVertexCount() !== undefined, null, { timeout: 10000 });
  const [, selT] = await page.evaluate(() => window.paretomesh.selectedObjectives()); // [front index or −1, T, E]
  assert.ok(Number.isInteger(selT) && selT >= 2);
  assert.match(await page.locator('#selection-info').textContent(), new RegExp(`T = ${selT} triangles`));
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(shots, 'compare-04-selected.png') });
  const tradeOff = picks[3].picks[2];
  await page.click('#compare-picks tr[data-method="greedy"] td[data-pick="trade-off"]');
  await page.waitForFunction((t) => window.paretomesh.selectedObjectives()?.[1] === t, tradeOff.t, { timeout: 10000 });
  assert.deepEqual(await page.evaluate(() => Array.from(window.paretomesh.selectedObjectives()).slice(1)), [tradeOff.t, tradeOff.e]);

  // 6. Compare mode off: the single-run plot is back.
  await page.uncheck('#compare-on');
  assert.ok(await page.locator('#plot').isVisible());
  assert.ok(!(await page.locator('#compare-plot').isVisible()));

  assert.deepEqual(realErrors(page), [], 'no page errors');

  const within = frames.filter((d) => d <= 20).length / Math.max(1, frames.length);
  const sorted = [...frames].sort((a, b) => a - b);
  const p95 = sorted[Math.floor(0.95 * (sorted.length - 1))] ?? 0;
  console.log(`compare e2e ok: population ${POPULATION}, ${GENERATIONS} generations, seed ${SEED}; ` +
    `fronts ${lengths.join('/')} (NSGA-II/weighted/decimation/greedy/memetic); ${evaluations} evaluations; ` +
    `done ${(wallMs / 1000).toFixed(1)} s after the click, ${(optimisingMs / 1000).toFixed(1)} s of it optimising ` +
    `(${((100 * optimisingMs) / wallMs).toFixed(0)} % of wall time); ` +
    `${(100 * within).toFixed(1)} % of ${frames.length} frames within 20 ms, 95th percentile ${p95.toFixed(1)} ms; ` +
    `${liveTables} distinct live tables before the final one`);
});
