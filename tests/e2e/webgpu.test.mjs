// The WebGPU renderer, tested headless in Chromium (playwright-core driving /usr/bin/chromium).
//
// Chromium offers a WebGPU adapter headless only with --enable-unsafe-webgpu (on SwiftShader),
// and even then a WebGPU canvas presents nothing a screenshot can see: it reads back white. A
// texture read back with copyTextureToBuffer does hold what was drawn. So this test launches
// Chromium with that flag, has the app render the built-in surface and a simplified mesh (its
// wireframe and error map on) into an OFFSCREEN texture with the WebGPU backend forced
// (`renderOffscreen` in src/web/bindings.rs), reads the pixels back, and checks the surface
// covers a plausible share of the frame and the wireframe and error colours are there. The
// same scenes are rendered with the WebGL2 backend, and the two images must agree within a
// tolerance (rasterisation rules and line drawing differ a little between the backends).
// The page itself runs with ?webgl, so its own canvas stays on the WebGL2 path. Last, a page
// without flags must take WebGPU, and one with ?webgpu-fail (a device request the browser
// refuses) must fall back to WebGL2.
import path from 'node:path';
import { writeFileSync } from 'node:fs';
import assert from 'node:assert/strict';
import { shots, withApp, newPage, realErrors, waitForApp, pixelVariance } from './harness.mjs';

const WIDTH = 320;
const HEIGHT = 240;

await withApp(async ({ browser, url }) => {
  const page = await newPage(browser);
  await page.goto(`${url}?webgl`);
  await waitForApp(page);
  assert.ok(await page.evaluate(() => 'gpu' in navigator && navigator.gpu.requestAdapter().then((a) => a !== null)),
    'Chromium offers a WebGPU adapter with --enable-unsafe-webgpu');

  // Renders `scene` with `backend`; returns the pixel statistics, the pixels and a PNG.
  const render = (backend, scene) => page.evaluate(async ({ backend, scene, w, h }) => {
    const m = await import('/www/pkg/paretomesh.js');
    const r = await m.renderOffscreen(backend, scene, w, h);
    const p = r.pixels;
    let background = 0, dark = 0, warm = 0, cool = 0;
    for (let i = 0; i < p.length; i += 4) {
      const [red, green, blue] = [p[i], p[i + 1], p[i + 2]];
      if (Math.abs(red - 237) <= 6 && Math.abs(green - 240) <= 6 && Math.abs(blue - 245) <= 6) background++;
      else if (Math.max(red, green, blue) < 90 && Math.abs(red - blue) < 40) dark++;
      else if (red > 150 && blue < 100) warm++;
      else if (blue > red + 40) cool++;
    }
    const n = p.length / 4;
    const c = new OffscreenCanvas(r.width, r.height);
    c.getContext('2d').putImageData(new ImageData(new Uint8ClampedArray(p), r.width, r.height), 0, 0);
    const png = new Uint8Array(await (await c.convertToBlob({ type: 'image/png' })).arrayBuffer());
    return {
      backend: r.backend, covered: 1 - background / n, dark: dark / n, warm: warm / n, cool: cool / n,
      pixels: Array.from(p), png: btoa(String.fromCharCode(...png)),
    };
  }, { backend, scene, w: WIDTH, h: HEIGHT });

  const results = {};
  for (const backend of ['webgpu', 'webgl2']) {
    for (const scene of ['surface', 'mesh']) {
      const r = await render(backend, scene);
      assert.equal(r.backend, backend === 'webgpu' ? 'WebGPU' : 'WebGL2', `${backend} was used`);
      writeFileSync(path.join(shots, `offscreen-${backend}-${scene}.png`), Buffer.from(r.png, 'base64'));
      results[`${backend} ${scene}`] = r;
      // The surface fills a plausible share of the frame: not blank, not all surface.
      assert.ok(r.covered > 0.15 && r.covered < 0.95, `${backend} ${scene}: ${(100 * r.covered).toFixed(1)} % covered`);
    }
    const surface = results[`${backend} surface`];
    const mesh = results[`${backend} mesh`];
    // The full surface has its grid wireframe; the simplified mesh its own wireframe and the
    // error map (dark blue where it is exact through teal and yellow to red).
    assert.ok(surface.dark > 0.005, `${backend}: the grid wireframe (${(100 * surface.dark).toFixed(2)} % dark)`);
    assert.ok(surface.warm < 0.001 && surface.cool < 0.001, `${backend}: no error colours on the plain surface`);
    assert.ok(mesh.dark > 0.002, `${backend}: the mesh wireframe (${(100 * mesh.dark).toFixed(2)} % dark)`);
    assert.ok(mesh.warm > 0.002, `${backend}: large errors in warm colours (${(100 * mesh.warm).toFixed(2)} %)`);
    assert.ok(mesh.cool > 0.02, `${backend}: small errors in cool colours (${(100 * mesh.cool).toFixed(2)} %)`);
  }

  // The two backends draw the same image within a tolerance.
  const agreement = {};
  for (const scene of ['surface', 'mesh']) {
    const a = results[`webgpu ${scene}`].pixels;
    const b = results[`webgl2 ${scene}`].pixels;
    assert.equal(a.length, b.length);
    let sum = 0, off = 0;
    for (let i = 0; i < a.length; i += 4) {
      let d = 0;
      for (let k = 0; k < 3; k++) d = Math.max(d, Math.abs(a[i + k] - b[i + k]));
      sum += d;
      if (d > 48) off++;
    }
    const n = a.length / 4;
    agreement[scene] = { mean: sum / n, off: off / n };
    assert.ok(sum / n < 6, `${scene}: mean difference ${(sum / n).toFixed(2)} per pixel`);
    assert.ok(off / n < 0.03, `${scene}: ${(100 * off / n).toFixed(2)} % of pixels differ by more than 48`);
  }

  assert.deepEqual(realErrors(page), [], 'no page errors');

  // With no flag the page's own view takes WebGPU: its device, canvas configuration and
  // pipelines pass the checks that send a failing WebGPU to WebGL2 (the canvas itself presents
  // nothing a headless screenshot can see, see the header).
  const direct = await newPage(browser);
  await direct.goto(url);
  await waitForApp(direct);
  assert.equal(await direct.locator('#backend').textContent(), 'WebGPU', 'the page uses WebGPU when it works');
  assert.deepEqual(realErrors(direct), [], 'no page errors on WebGPU');
  await direct.close();

  // An adapter whose device request fails: ?webgpu-fail asks for more bind groups than the
  // adapter has, so the browser refuses the device after the canvas gave a WebGPU context. The
  // page must fall back to WebGL2 on a fresh canvas, say why in the console, draw the surface
  // and still orbit with the mouse on the canvas that replaced the first.
  const failing = await newPage(browser);
  const warnings = [];
  failing.on('console', (m) => { if (m.type() === 'warning') warnings.push(m.text()); });
  await failing.goto(`${url}?webgpu-fail`);
  await waitForApp(failing);
  assert.equal(await failing.locator('#backend').textContent(), 'WebGL2', 'the view fell back to WebGL2');
  assert.ok(warnings.some((w) => /WebGPU .*cannot draw .*cannot open the GPU device.*falling back to WebGL2/s.test(w)),
    `the console says why: ${JSON.stringify(warnings)}`);
  assert.equal(await failing.locator('canvas#view').count(), 1, 'one view canvas');
  assert.ok(await failing.evaluate(() => document.getElementById('view').getContext('webgl2') !== null),
    'the view canvas is a WebGL2 one');
  const before = await failing.locator('#view').screenshot();
  writeFileSync(path.join(shots, 'webgpu-fail-fallback.png'), before);
  const fallbackVariance = await pixelVariance(failing, before);
  assert.ok(fallbackVariance > 50, `the fallback draws the surface (pixel variance ${fallbackVariance.toFixed(1)})`);
  const box = await failing.locator('#view').boundingBox();
  await failing.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await failing.mouse.down();
  await failing.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2, { steps: 5 });
  await failing.mouse.up();
  await failing.waitForTimeout(300);
  const after = await failing.locator('#view').screenshot();
  assert.ok(!before.equals(after), 'dragging on the fresh canvas orbits the view');
  assert.deepEqual(realErrors(failing), [], 'no page errors on the fallback');

  const pct = (x) => `${(100 * x).toFixed(1)} %`;
  console.log(`webgpu e2e ok: ${Object.entries(results).map(([k, r]) => `${k}: ${pct(r.covered)} covered, ${pct(r.dark)} wireframe, ${pct(r.warm)} warm, ${pct(r.cool)} cool`).join('; ')}; ` +
    `backends agree: ${Object.entries(agreement).map(([s, a]) => `${s} mean ${a.mean.toFixed(2)}, ${pct(a.off)} off`).join('; ')}`);
}, {
  // --enable-unsafe-webgpu: the only way to get a WebGPU adapter in headless Chromium here (see
  // the header); no --disable-gpu, which would take the adapter away.
  args: ['--no-sandbox', '--enable-unsafe-webgpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
