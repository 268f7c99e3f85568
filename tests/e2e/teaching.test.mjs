// End-to-end test of the teaching view in headless Chromium: on the built-in surface with a
// small NSGA-II, "Next phase" walks selection → crossover → mutation → evaluation → sorting →
// crowding → survival of generation 1 with a caption per phase and a drawn plot; hovering a
// point reads out its front and crowding distance; the OAX panel lists the array with a
// thumbnail per mesh, and clicking one shows that mesh in the 3-D view; "Next generation"
// goes to the next survival; slow-motion play advances phases by itself.
import path from 'node:path';
import assert from 'node:assert/strict';
import { shots, withApp, newPage, realErrors, waitForApp, pixelVariance } from './harness.mjs';

const PHASES = ['selection', 'crossover', 'mutation', 'evaluation', 'non-dominated sorting', 'crowding distance', 'survival'];

await withApp(async ({ browser, url }) => {
  const page = await newPage(browser);
  await page.goto(url);
  await waitForApp(page);
  // Teaching mode walks NSGA-II's generation; the app's default is the memetic method.
  await page.selectOption('#algorithm', 'nsga2');
  await page.fill('#population', '16');
  await page.fill('#generations', '6');
  await page.check('#teach');
  await page.waitForSelector('#teaching', { state: 'visible', timeout: 5000 });

  const state = () => page.evaluate(() => window.paretomesh.teachingState() ?? null);
  const caption = () => page.locator('#teach-caption').textContent();

  // Generation 1, phase by phase.
  const captions = [];
  for (const [i, phase] of PHASES.entries()) {
    await page.click('#teach-phase');
    await page.waitForFunction((p) => (window.paretomesh.teachingState() ?? [])[0] === p, phase, { timeout: 60000 });
    const [shown, generation] = await state();
    assert.equal(shown, phase);
    assert.equal(generation, '1');
    await page.waitForFunction((p) => document.getElementById('teach-caption').textContent.includes(p), phase);
    captions.push(await caption());
    assert.match(captions[i], new RegExp(`^Generation 1 · ${phase}: `));
    assert.equal(await page.locator('#teach-phases li.current').textContent(), phase, 'the phase list marks it');
    const plot = await page.locator('#plot').screenshot({ path: path.join(shots, `teach-${i + 1}-${phase.split(' ')[0]}.png`) });
    assert.ok(await pixelVariance(page, plot) > 50, `${phase}: the plot is drawn`);
  }
  assert.match(captions[0], /tournaments picked \d+ of the 16 individuals/);
  assert.match(captions[6], /16 of 32 survive/);

  // Crowding on hover, at survival: find a mark by sweeping the plot.
  const box = await page.locator('#plot').boundingBox();
  let hover = '';
  for (let y = 20; y < box.height - 40 && !hover; y += 4) {
    for (let x = 70; x < box.width - 14 && !hover; x += 4) {
      await page.mouse.move(box.x + x, box.y + y);
      hover = await page.locator('#teach-hover').textContent();
    }
  }
  assert.match(hover, /(parent|child) \d+ · F\d+ · crowding (∞|\d+\.\d{3}) · T = \d+/, `hover read-out: ${hover}`);
  assert.match(hover, /survives|dropped/);

  // The OAX panel: parents, the array's rows and the best-levels child, each with a thumbnail.
  const rows = await page.locator('#oax table.oax tr.row').count();
  assert.ok(rows >= 2, `array rows listed (${rows})`);
  assert.equal(await page.locator('#oax canvas[data-mesh]').count(), rows + 3);
  assert.equal(await page.locator('#oax tr.effects').count(), 2, 'the factor effects');
  const thumb = await page.locator('#oax canvas[data-mesh="2"]').screenshot();
  assert.ok(await pixelVariance(page, thumb) > 20, 'the thumbnail shows a mesh');
  const rowT = Number(await page.locator('#oax tr.row').first().locator('td.t').textContent());
  await page.click('#oax canvas[data-mesh="2"]');
  await page.waitForFunction(() => window.paretomesh.selectedObjectives() !== undefined);
  const [, selectedT] = await page.evaluate(() => window.paretomesh.selectedObjectives());
  assert.equal(selectedT, rowT, 'the clicked row is shown in the 3-D view');
  await page.screenshot({ path: path.join(shots, 'teach-8-oax.png'), fullPage: true });

  // One whole generation.
  await page.click('#teach-generation');
  await page.waitForFunction(() => { const s = window.paretomesh.teachingState(); return s && s[1] === '2' && s[0] === 'survival'; }, null, { timeout: 60000 });

  // Slow motion: play at 0.3 s per phase; it reaches generation 3's crowding by itself.
  await page.locator('#teach-speed').fill('0.3');
  await page.click('#teach-play');
  await page.waitForFunction(() => { const s = window.paretomesh.teachingState(); return s && s[1] === '3' && s[0] === 'crowding distance'; }, null, { timeout: 60000 });
  await page.click('#teach-play');
  await page.waitForFunction(() => document.getElementById('teach-play').textContent === 'Play');
  const pausedAt = await state();
  await page.waitForTimeout(1000);
  assert.deepEqual(await state(), pausedAt, 'paused play stays on its phase');

  assert.deepEqual(realErrors(page), [], 'no page errors');
  console.log(`teaching e2e ok: 7 phases of generation 1 with captions, ${rows} OAX rows with thumbnails; ` +
    `survival caption: ${captions[6]}; hover: ${hover}`);
});
