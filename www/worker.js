// Parses dropped files off the main thread, so a file of tens of MB never freezes the page.
// Runs the same wasm module as the page; posts the height field back with its heights as a
// transferable Float64Array (see src/web/transfer.rs). Keeps the last file so the import
// dialog can re-parse it with another projection or grid size.
import init, { parseSurface } from './pkg/paretomesh.js';

const ready = init();
let last = null;

self.onmessage = async ({ data }) => {
  const { id, projection = 'auto', width = 0, height = 0 } = data;
  try {
    await ready;
    if (data.bytes) last = { name: data.name, bytes: data.bytes, sidecar: data.sidecar };
    if (!last) throw new Error('no file to parse');
    const surface = parseSurface(last.name, last.bytes, last.sidecar, projection, width, height);
    self.postMessage({ id, ok: true, surface }, [surface.z.buffer]);
  } catch (e) {
    self.postMessage({ id, ok: false, error: e instanceof Error ? e.message : String(e) });
  }
};
