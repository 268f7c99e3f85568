// Parses dropped files off the main thread, so a file of tens of MB never freezes the page.
// Runs the same wasm module as the page; posts the height field back with its heights as a
// transferable Float64Array (see src/web/transfer.rs).
import init, { parseSurface } from './pkg/paretomesh.js';

const ready = init();

self.onmessage = async ({ data }) => {
  const { id, name, bytes, sidecar } = data;
  try {
    await ready;
    const surface = parseSurface(name, bytes, sidecar);
    self.postMessage({ id, ok: true, surface }, [surface.z.buffer]);
  } catch (e) {
    self.postMessage({ id, ok: false, error: e instanceof Error ? e.message : String(e) });
  }
};
