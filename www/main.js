// Boots the wasm app, wires the file drop and picker, and runs the requestAnimationFrame loop.
// Everything else (controls, plot, 3-D view, parsing, exports) lives in Rust (src/web/).
import init, { start, drawPreview } from './pkg/paretomesh.js';
import { WorkerPool } from './pool.js';

const $ = (id) => document.getElementById(id);
let app = null;
let pool = null;
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

// Parsing happens in a module Worker running the same wasm (www/worker.js); null when the
// browser cannot start one.
let worker = null;
let nextId = 0;
const pending = new Map();
function parseInWorker(name, bytes, sidecar, options = {}) {
  try {
    if (!worker) {
      worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
      worker.onmessage = ({ data }) => { pending.get(data.id)?.(data); pending.delete(data.id); };
      worker.onerror = (e) => {
        for (const resolve of pending.values()) resolve({ ok: false, error: `the parser stopped: ${e.message}` });
        pending.clear();
        worker = null;
      };
    }
  } catch {
    return Promise.resolve(null);
  }
  const id = nextId++;
  return new Promise((resolve) => {
    pending.set(id, resolve);
    // A re-parse (bytes null) uses the file the Worker kept.
    const transfer = bytes ? [bytes.buffer, ...(sidecar ? [sidecar.buffer] : [])] : [];
    worker.postMessage({ id, name, bytes, sidecar, ...options }, transfer);
  });
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
    const result = await parseInWorker(main.name, bytes, side);
    if (result === null) {
      // No Worker (very old browser): parse here, after the message has painted.
      await new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0)));
      app.loadFile(main.name, bytes, side);
    } else if (result.ok && result.surface.resampled) {
      // A share link waiting for this mesh says how to grid it: no dialog, the link's choice.
      const wanted = app.pendingImport();
      if (wanted) {
        const again = await parseInWorker(main.name, null, null, wanted);
        if (again?.ok) app.loadParsed(main.name, again.surface, again.size, again.hash, wanted.projection, wanted.surface);
        else app.showLoadMessage(again ? again.error : 'the parser is not available', true);
      } else {
        openImportDialog(main.name, result.surface, result.size, result.hash, { georeference: result.surface.georeferenceSummary });
      }
    } else if (result.ok) {
      if (app.loadParsed(main.name, result.surface, result.size, result.hash) && result.surface.georeferenceSummary) {
        app.showLoadMessage(`loaded ${main.name} · ${result.surface.georeferenceSummary}`, false);
      }
    } else if (result.folds) {
      // A closed or thick mesh: offer its outer surface instead of only refusing it.
      const wanted = app.pendingImport();
      const options = wanted ?? { projection: 'auto', surface: 'outer', width: 0, height: 0 };
      const outer = await parseInWorker(main.name, null, null, { ...options, surface: options.surface ?? 'outer' });
      if (!outer?.ok) app.showLoadMessage(outer ? outer.error : result.error, true);
      else if (wanted) app.loadParsed(main.name, outer.surface, outer.size, outer.hash, wanted.projection, wanted.surface);
      else openImportDialog(main.name, outer.surface, outer.size, outer.hash, { folds: result.error });
    } else {
      app.showLoadMessage(result.error, true);
    }
  } catch (e) {
    app.showLoadMessage(`${main.name}: cannot read the file (${e})`, true);
  } finally {
    bar.hidden = true;
  }
}

// The dialog for a file that is not a grid as it stands: a mesh (projection, surface and grid
// size), a mesh that folds (offered as its outer surface, with how much of the grid was covered
// more than once), or a GeoTIFF over the size limit (grid size, with its georeferencing). Each
// choice is re-parsed in the Worker (which kept the file) with a preview; nothing changes until
// "Use this grid".
let importing = null;
const dialogKey = () => `${$('import-projection').value} ${$('import-surface').value} ${Number($('import-width').value) || 0} ${Number($('import-height').value) || 0}`;
function openImportDialog(name, surface, size, hash, { folds = null, georeference = null } = {}) {
  const geotiff = georeference !== null && georeference !== undefined;
  $('import-title').textContent = geotiff ? 'This GeoTIFF is larger than one tab holds: its native size is in the summary'
    : folds ? 'This mesh folds over itself' : 'This mesh is not a grid';
  $('import-projection-row').hidden = geotiff;
  $('import-surface-row').hidden = geotiff;
  $('import-projection').value = 'auto';
  $('import-surface').value = folds ? 'outer' : 'single';
  $('import-georeference').hidden = !geotiff;
  $('import-georeference').textContent = geotiff ? `georeferencing: ${georeference}` : '';
  $('import-folds').hidden = !folds;
  $('import-folds').textContent = folds ? `As a single surface: ${folds.replace(/^[^:]*: /, '').replace(/; a closed or thick mesh.*$/, '')}. Its outer surface is shown instead.` : '';
  $('import-summary').textContent = surface.source;
  $('import-width').value = surface.width;
  $('import-height').value = surface.height;
  $('import-message').textContent = '';
  importing = { name, surface, size, hash, key: dialogKey() };
  drawPreview('import-preview', surface);
  app.showLoadMessage(`${name}: choose how to turn it into a grid`, false);
  $('import-dialog').showModal();
}
async function previewImport() {
  const options = {
    projection: $('import-projection').value,
    surface: $('import-surface').value,
    width: Number($('import-width').value) || 0,
    height: Number($('import-height').value) || 0,
  };
  $('import-message').textContent = 'resampling…';
  importing.key = dialogKey();
  const result = await parseInWorker(importing.name, null, null, options);
  if (result?.ok) {
    importing.surface = result.surface;
    $('import-summary').textContent = result.surface.source;
    $('import-message').textContent = '';
    drawPreview('import-preview', result.surface);
    return true;
  }
  $('import-message').textContent = result ? result.error : 'the parser is not available';
  return false;
}
function wireImportDialog() {
  $('import-apply').addEventListener('click', previewImport);
  $('import-use').addEventListener('click', async () => {
    if (dialogKey() !== importing.key && !(await previewImport())) return;
    $('import-dialog').close();
    app.loadParsed(importing.name, importing.surface, importing.size, importing.hash, $('import-projection').value, $('import-surface').value);
  });
  $('import-cancel').addEventListener('click', () => {
    $('import-dialog').close();
    app.showLoadMessage(`${importing.name}: not loaded; the current surface stays`, false);
  });
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
    pool.pump();
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
  const flags = new URLSearchParams(location.search);
  // ?webgl: WebGL2 only; ?webgpu-fail: a WebGPU device request the browser refuses, to see the
  // fallback to WebGL2.
  app = await start(flags.has('webgl'), flags.has('webgpu-fail'));
  window.paretomesh = app; // for the console and the end-to-end test
  // Tiled runs go to one Web Worker per core; ?workers sends untiled runs there too, and
  // ?tile=N cuts grids with a side over N points (else the CLI's default tile size).
  pool = new WorkerPool(app);
  window.paretomeshPool = pool; // its job log, for benchmarks
  app.setPoolSetup(navigator.hardwareConcurrency || 1, flags.has('workers'), Number(flags.get('tile')) || 0);
  if (location.hash.length > 1) app.openLink(location.hash); // a share link
  wireDrop();
  wireImportDialog();
  requestAnimationFrame(loop);
} catch (e) {
  $('panic-message').textContent = `the app could not start: ${e}`;
  $('panic').hidden = false;
}
