// Boots the wasm app, wires the file drop and picker, and runs the requestAnimationFrame loop.
// Everything else (controls, plot, 3-D view, parsing, exports) lives in Rust (src/web/).
import init, { start } from './pkg/paretomesh.js';

const $ = (id) => document.getElementById(id);
let app = null;
let stopped = false;

// Reads a file in chunks so a big file shows progress and the tab stays responsive.
async function readWithProgress(file, onProgress) {
  const out = new Uint8Array(file.size);
  const reader = file.stream().getReader();
  let at = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    out.set(value, at);
    at += value.length;
    onProgress(at / Math.max(1, file.size));
  }
  return out;
}

async function loadFiles(files) {
  if (!app || files.length === 0) return;
  const list = [...files];
  const main = list.find((f) => !f.name.toLowerCase().endsWith('.json')) ?? list[0];
  const stem = main.name.replace(/\.[^.]*$/, '');
  const sidecar = list.find((f) => f !== main && f.name.toLowerCase() === `${stem.toLowerCase()}.json`)
    ?? list.find((f) => f !== main && f.name.toLowerCase().endsWith('.json'));
  const bar = $('load-progress');
  bar.hidden = false;
  try {
    const total = main.size + (sidecar ? sidecar.size : 0);
    const progress = (done) => {
      bar.value = done / Math.max(1, total);
      app.showLoadMessage(`reading ${main.name}: ${Math.round((100 * done) / Math.max(1, total))} %`, false);
    };
    const bytes = await readWithProgress(main, (f) => progress(f * main.size));
    const side = sidecar ? await readWithProgress(sidecar, (f) => progress(main.size + f * sidecar.size)) : undefined;
    app.showLoadMessage(`parsing ${main.name}…`, false);
    // Let the message paint before parsing.
    await new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0)));
    app.loadFile(main.name, bytes, side);
  } catch (e) {
    app.showLoadMessage(`${main.name}: cannot read the file (${e})`, true);
  } finally {
    bar.hidden = true;
  }
}

function wireDrop() {
  const overlay = $('drop-overlay');
  let depth = 0;
  window.addEventListener('dragenter', (e) => { e.preventDefault(); depth++; overlay.hidden = false; });
  window.addEventListener('dragleave', () => { depth = Math.max(0, depth - 1); if (depth === 0) overlay.hidden = true; });
  window.addEventListener('dragover', (e) => e.preventDefault());
  window.addEventListener('drop', (e) => {
    e.preventDefault();
    depth = 0;
    overlay.hidden = true;
    loadFiles(e.dataTransfer.files);
  });
  $('file-input').addEventListener('change', (e) => loadFiles(e.target.files));
}

function loop(now) {
  if (stopped) return;
  try {
    app.frame(now);
  } catch (e) {
    // A Rust panic: the panic hook has shown the message; stop the loop.
    stopped = true;
    $('panic').hidden = false;
    if (!$('panic-message').textContent) $('panic-message').textContent = String(e);
    return;
  }
  requestAnimationFrame(loop);
}

$('panic-reset').addEventListener('click', () => location.reload());

try {
  await init();
  const forceWebgl = new URLSearchParams(location.search).has('webgl');
  app = await start(forceWebgl);
  window.paretomesh = app; // for the console and the end-to-end test
  wireDrop();
  requestAnimationFrame(loop);
} catch (e) {
  $('panic-message').textContent = `the app could not start: ${e}`;
  $('panic').hidden = false;
}
