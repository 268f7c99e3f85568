// What every end-to-end test needs: the repository root, a static server for the built app
// (www/pkg must exist: scripts/build-web.sh), headless Chromium through playwright-core, file
// drops through a real DataTransfer, and a blank-canvas check.
import { chromium } from 'playwright-core';
import { spawn } from 'node:child_process';
import { createServer } from 'node:net';
import { mkdirSync, existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';
import assert from 'node:assert/strict';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
export const shots = path.join(root, 'target/e2e');
mkdirSync(shots, { recursive: true });
assert.ok(existsSync(path.join(root, 'www/pkg/paretomesh_bg.wasm')), 'build the app first: bash scripts/build-web.sh');

function freePort() {
  return new Promise((resolve, reject) => {
    const s = createServer();
    s.once('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

async function waitForServer(url, tries = 100) {
  for (let i = 0; i < tries; i++) {
    try {
      const r = await fetch(url);
      if (r.ok) return;
    } catch { /* not up yet */ }
    await new Promise((r) => setTimeout(r, 100));
  }
  throw new Error(`server at ${url} did not start`);
}

// Serves the repository, starts Chromium, runs `body({ browser, url })`, and always cleans up.
export async function withApp(body) {
  const port = await freePort();
  const server = spawn('python3', ['-m', 'http.server', '--bind', '127.0.0.1', String(port)], { cwd: root, stdio: 'ignore' });
  const url = `http://127.0.0.1:${port}/`;
  let browser;
  try {
    await waitForServer(url);
    browser = await chromium.launch({
      executablePath: '/usr/bin/chromium',
      // No --enable-unsafe-webgpu: a WebGPU canvas stays blank headless, so the app takes WebGL2.
      args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    });
    await body({ browser, url });
  } finally {
    if (browser) await browser.close();
    server.kill();
  }
}

// A new page whose errors (uncaught exceptions, console errors) collect in `page.errors`.
export async function newPage(browser) {
  const page = await browser.newPage({ viewport: { width: 1400, height: 850 }, acceptDownloads: true });
  page.errors = [];
  page.on('pageerror', (e) => page.errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') page.errors.push(m.text()); });
  return page;
}

// The page's errors, less the GPU driver chatter of headless WebGL.
export const realErrors = (page) => page.errors.filter((e) => !/GPU stall|WebGL-/.test(e));

// Waits until the app has started and painted once.
export async function waitForApp(page) {
  await page.waitForFunction(() => performance.getEntriesByName('paretomesh-first-paint').length > 0, null, { timeout: 30000 });
}

// Drops files (name → bytes) on the drop zone through a real DataTransfer.
export async function dropFiles(page, files) {
  const payload = files.map(({ name, bytes }) => ({ name, b64: Buffer.from(bytes).toString('base64') }));
  await page.evaluate((items) => {
    const dt = new DataTransfer();
    for (const { name, b64 } of items) {
      const bin = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
      dt.items.add(new File([bin], name));
    }
    const zone = document.getElementById('drop-zone');
    for (const type of ['dragenter', 'dragover', 'drop']) {
      zone.dispatchEvent(new DragEvent(type, { dataTransfer: dt, bubbles: true, cancelable: true }));
    }
  }, payload);
}

// Pixel variance (over RGB) of a PNG screenshot, decoded in the page.
export async function pixelVariance(page, png) {
  return page.evaluate(async (b64) => {
    const bin = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
    const bitmap = await createImageBitmap(new Blob([bin], { type: 'image/png' }));
    const c = new OffscreenCanvas(bitmap.width, bitmap.height);
    const ctx = c.getContext('2d');
    ctx.drawImage(bitmap, 0, 0);
    const d = ctx.getImageData(0, 0, bitmap.width, bitmap.height).data;
    let n = 0, sum = 0, sq = 0;
    for (let i = 0; i < d.length; i += 4) {
      for (let k = 0; k < 3; k++) { sum += d[i + k]; sq += d[i + k] * d[i + k]; n++; }
    }
    const mean = sum / n;
    return sq / n - mean * mean;
  }, png.toString('base64'));
}

// A W×H grid with its (x, y) jittered, as OBJ: a surface mesh whose vertices are not a lattice.
export function wavyObj(w, h) {
  let obj = '';
  for (let y = 0; y < h; y++) {
    for (let x = 0; x < w; x++) {
      const jx = x + 0.3 * Math.sin(7 * x + 3 * y);
      const jy = y + 0.3 * Math.cos(5 * x + 11 * y);
      obj += `v ${jx} ${jy} ${3 * Math.sin(jx / 4) + 2 * Math.cos(jy / 3)}\n`;
    }
  }
  for (let y = 0; y < h - 1; y++) {
    for (let x = 0; x < w - 1; x++) {
      const a = y * w + x + 1;
      obj += `f ${a} ${a + 1} ${a + w}\nf ${a + 1} ${a + w + 1} ${a + w}\n`;
    }
  }
  return obj;
}
