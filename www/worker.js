// Parses dropped files off the main thread, so a file of tens of MB never freezes the page, and
// fingerprints them (size and FNV-1a hash) for share links.
// Runs the same wasm module as the page; posts the height field back with its heights as a
// transferable Float64Array (see src/web/transfer.rs). Keeps the last file so the import
// dialog can re-parse it with another projection or grid size.
import init, { parseSurface, fnv1a64Hex } from './pkg/paretomesh.js';

const ready = init();
let last = null;

self.onmessage = async ({ data }) => {
  const { id, projection = 'auto', surface: wall = 'single', width = 0, height = 0 } = data;
  try {
    await ready;
    // The fingerprint a share link gives the file, hashed here off the page's thread.
    if (data.bytes) last = { name: data.name, bytes: data.bytes, sidecar: data.sidecar, size: data.bytes.length, hash: fnv1a64Hex(data.bytes) };
    if (!last) throw new Error('no file to parse');
    const surface = parseSurface(last.name, last.bytes, last.sidecar, projection, wall, width, height);
    self.postMessage({ id, ok: true, surface, size: last.size, hash: last.hash }, [surface.z.buffer]);
  } catch (e) {
    // `folds`: a mesh that folds in every projection, whose outer surface can still be read.
    self.postMessage({ id, ok: false, error: e instanceof Error ? e.message : String(e), folds: Boolean(e?.folds) });
  }
};
