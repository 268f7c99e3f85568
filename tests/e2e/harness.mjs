// What every end-to-end test needs: the repository root, a static server for the built app
// (www/pkg must exist: scripts/build-web.sh), headless Chromium through playwright-core, file
// drops through a real DataTransfer, and a blank-canvas check.
import { chromium } from 'playwright-core';
import { spawn } from 'node:child_process';
import { createServer } from 'node:net';
import { mkdirSync, existsSync } from 'node:fs';
import { deflateSync } from 'node:zlib';
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
// `args` replaces the browser flags (the WebGPU test needs its own).
export async function withApp(body, { args = null } = {}) {
  const port = await freePort();
  const server = spawn('python3', ['-m', 'http.server', '--bind', '127.0.0.1', String(port)], { cwd: root, stdio: 'ignore' });
  const url = `http://127.0.0.1:${port}/`;
  let browser;
  try {
    await waitForServer(url);
    browser = await chromium.launch({
      executablePath: '/usr/bin/chromium',
      // No --enable-unsafe-webgpu: a WebGPU canvas stays blank headless, so the app takes WebGL2.
      args: args ?? ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
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

// Starts logging the intervals between animation frames in the page (a fresh log each call).
export async function startFrameLog(page) {
  await page.evaluate(() => {
    window.__frames = [];
    window.__stopFrames = false;
    let last = performance.now();
    const tick = (t) => { window.__frames.push(t - last); last = t; if (!window.__stopFrames) requestAnimationFrame(tick); };
    requestAnimationFrame(tick);
  });
}

// The number of frame intervals logged so far.
export const frameCount = (page) => page.evaluate(() => window.__frames.length);

// Stops the frame log and returns its intervals (ms).
export const stopFrameLog = (page) => page.evaluate(() => { window.__stopFrames = true; return window.__frames; });

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

// The front indices the paper's trade-off pick (eq. 7-9) can give for `front` ([T, E] pairs):
// the mean score over random weights w equals the score at their mean w̄, which for 1000
// uniform weights lies within 0.5 ± 0.05 (more than five standard deviations), so the pick is
// the minimiser of α·w̄·E + (1 − w̄)·T for some w̄ in that window (α = mean T/E over E > 0).
export function tradeOffCandidates(front) {
  const ratios = front.filter(([, e]) => e > 0).map(([t, e]) => t / e);
  const alpha = ratios.length ? ratios.reduce((a, b) => a + b, 0) / ratios.length : 0;
  const picks = new Set();
  for (let w = 0.45; w <= 0.5501; w += 0.0025) {
    let best = 0;
    front.forEach(([t, e], i) => {
      const [bt, be] = front[best];
      const s = alpha * w * e + (1 - w) * t, sb = alpha * w * be + (1 - w) * bt;
      if (s < sb || (s === sb && (t < bt || (t === bt && e < be)))) best = i;
    });
    picks.add(best);
  }
  return picks;
}

// The front index of the knee of `front` ([T, E] pairs): each objective scaled to [0, 1] over
// the front, the member nearest (0, 0); ties to the fewer triangles (the library's rule).
export function kneeIndex(front) {
  const span = (k) => {
    const v = front.map((p) => p[k]);
    const lo = Math.min(...v);
    return [lo, Math.max(...v) - lo];
  };
  const [[t0, dt], [e0, de]] = [span(0), span(1)];
  const scaled = (v, lo, d) => (d > 0 ? (v - lo) / d : 0);
  let best = 0;
  front.forEach(([t, e], i) => {
    const d = Math.hypot(scaled(t, t0, dt), scaled(e, e0, de));
    const [bt, be] = front[best];
    const db = Math.hypot(scaled(bt, t0, dt), scaled(be, e0, de));
    if (d < db || (d === db && t < bt)) best = i;
  });
  return best;
}

// A closed, thick tube along z as OBJ: an outer wall of radius 1 + 0.1·sin 3θ + 0.1·cos ζ, an
// inner wall 5 % inside it, and annular caps joining them; like a printable scan's shell, it
// folds over itself in every projection, but its outer wall is a cylindrical height field.
export function thickTubeObj(angles = 48, rows = 21) {
  let obj = '';
  const index = (wall, row, a) => 1 + wall * rows * angles + row * angles + (a % angles);
  for (const scale of [1, 0.95]) {
    for (let r = 0; r < rows; r++) {
      const zeta = -2 + (4 * r) / (rows - 1);
      for (let a = 0; a < angles; a++) {
        const theta = (2 * Math.PI * a) / angles;
        const rho = scale * (1 + 0.1 * Math.sin(3 * theta) + 0.1 * Math.cos(zeta));
        obj += `v ${rho * Math.cos(theta)} ${rho * Math.sin(theta)} ${zeta}\n`;
      }
    }
  }
  for (let wall = 0; wall < 2; wall++) {
    for (let r = 0; r + 1 < rows; r++) {
      for (let a = 0; a < angles; a++) {
        const [p, q, s, t] = [index(wall, r, a), index(wall, r, a + 1), index(wall, r + 1, a + 1), index(wall, r + 1, a)];
        obj += wall === 0 ? `f ${p} ${q} ${s}\nf ${p} ${s} ${t}\n` : `f ${p} ${s} ${q}\nf ${p} ${t} ${s}\n`;
      }
    }
  }
  for (const r of [0, rows - 1]) {
    for (let a = 0; a < angles; a++) {
      const [p, q, s, t] = [index(0, r, a), index(0, r, a + 1), index(1, r, a + 1), index(1, r, a)];
      obj += `f ${p} ${q} ${s}\nf ${p} ${s} ${t}\n`;
    }
  }
  return obj;
}

// A single-band Int16 GeoTIFF (one Deflate strip) of `width`×`height` heights h(x, y), with
// ModelPixelScale, ModelTiepoint and GDAL_NODATA tags; written by hand (the container is
// small) so a test can make a grid too large to ship in tests/data.
export function int16GeoTiff(width, height, h, { scale = [30, 30, 0], tie = [0, 0, 0, 500000, 4000000, 0], nodata = '-32768' } = {}) {
  const samples = Buffer.alloc(width * height * 2);
  for (let y = 0; y < height; y++) for (let x = 0; x < width; x++) samples.writeInt16LE(h(x, y), 2 * (y * width + x));
  const strip = deflateSync(samples);
  const doubles = (xs) => { const b = Buffer.alloc(8 * xs.length); xs.forEach((v, i) => b.writeDoubleLE(v, 8 * i)); return b; };
  const ascii = Buffer.from(`${nodata}\0`, 'latin1');
  // [tag, type, count, value or data]; types: 3 SHORT, 4 LONG, 2 ASCII, 12 DOUBLE.
  const entries = [
    [256, 4, 1, width], [257, 4, 1, height], [258, 3, 1, 16], [259, 3, 1, 8], [262, 3, 1, 1],
    [273, 4, 1, 'strip'], [277, 3, 1, 1], [278, 4, 1, height], [279, 4, 1, strip.length], [339, 3, 1, 2],
    [33550, 12, 3, doubles(scale)], [33922, 12, 6, doubles(tie)], [42113, 2, ascii.length, ascii],
  ];
  const ifdSize = 2 + 12 * entries.length + 4;
  let extra = 8 + ifdSize;
  const blobs = [];
  const place = (buf) => { const at = extra; blobs.push(buf); extra += buf.length + (buf.length % 2); if (buf.length % 2) blobs.push(Buffer.alloc(1)); return at; };
  const ifd = Buffer.alloc(ifdSize);
  ifd.writeUInt16LE(entries.length, 0);
  const stripAt = [];
  entries.forEach(([tag, type, count, value], i) => {
    const o = 2 + 12 * i;
    ifd.writeUInt16LE(tag, o); ifd.writeUInt16LE(type, o + 2); ifd.writeUInt32LE(count, o + 4);
    if (value === 'strip') stripAt.push(o + 8);
    else if (Buffer.isBuffer(value)) {
      if (value.length <= 4) value.copy(ifd, o + 8); else ifd.writeUInt32LE(place(value), o + 8);
    } else if (type === 3) ifd.writeUInt16LE(value, o + 8);
    else ifd.writeUInt32LE(value, o + 8);
  });
  const stripOffset = place(strip);
  for (const o of stripAt) ifd.writeUInt32LE(stripOffset, o);
  const header = Buffer.from([0x49, 0x49, 42, 0, 8, 0, 0, 0]);
  return Buffer.concat([header, ifd, ...blobs]);
}
