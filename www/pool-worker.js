// One worker of the pool (www/pool.js): its own wasm instance, handed one job at a time with only
// that job's grid (see src/app/pool.rs). A whole-grid job posts its front as it grows and when
// it is done, as three transferable typed arrays; a tile job posts its tile's front (JSON) when
// done. A job that fails posts the message of what stopped it.
// The pool's mesh worker runs this script too: it keeps the whole grid (sent with its first
// job) and builds tiled members' meshes (`kind: 'mesh'`), posting them as typed arrays.
import init, { JobRunner, MeshGrid, runTile, keepPanicMessages, lastPanic } from './pkg/paretomesh.js';

// How often a running job posts its front: often enough to watch it grow, rarely enough that
// copying the front costs the job little.
const POST_MS = 400;

const ready = init().then(() => keepPanicMessages());
let grid = null;

function buildMesh(job) {
  if (job.grid) {
    grid?.free();
    grid = null;
    grid = new MeshGrid(job.grid.width, job.grid.height, job.grid.z);
  }
  if (!grid) throw new Error('the mesh worker has no grid');
  const start = performance.now();
  const m = grid.build(job.header, job.kept, job.offsets, job.toggles);
  const layers = m.layers.flatMap((l) => [l.vertices.buffer, l.indices.buffer]);
  self.postMessage({ kind: 'mesh', id: job.id, ms: performance.now() - start, ...m },
    [m.kept.buffer, m.triangles.buffer, m.pointError.buffer, ...layers]);
}

function messageOf(e) {
  let panic = null;
  try { panic = lastPanic(); } catch { /* the module did not start */ }
  return panic ?? (e instanceof Error ? e.message : String(e));
}

self.onmessage = async ({ data: job }) => {
  const { run, index } = job;
  try {
    await ready;
    if (job.kind === 'mesh') {
      buildMesh(job);
      return;
    }
    if (job.kind === 'tile') {
      const start = performance.now();
      const front = runTile(job.surface, job.plan, job.tile, job.config, job.seed, job.members);
      self.postMessage({ kind: 'tile', run, index, front, ms: performance.now() - start });
      return;
    }
    const runner = new JobRunner(job.surface, job.algorithm, job.params);
    for (;;) {
      const [evaluations, generation, done] = runner.runFor(POST_MS);
      const front = runner.front();
      self.postMessage({ kind: 'front', run, index, evaluations, generation, done: done === 1, ...front },
        [front.scores.buffer, front.offsets.buffer, front.kept.buffer]);
      if (done === 1) break;
    }
    runner.free();
  } catch (e) {
    if (job.kind === 'mesh') self.postMessage({ kind: 'mesh-error', id: job.id, message: messageOf(e) });
    else self.postMessage({ kind: 'error', run, index, message: messageOf(e) });
  }
};
