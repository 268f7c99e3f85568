// The pool of Web Workers that runs the app's pool runs (src/app/pool.rs), one worker per core.
// The app says which run is under way and hands out its jobs; this file starts workers, passes
// jobs and fronts between them and the app, and stops the workers of a run the app has left
// (reset, another surface, a failed worker). No SharedArrayBuffer: jobs and fronts travel by
// postMessage with transferables, so the app works from any static server.
// One more worker, the mesh worker, builds the selected member's mesh of a tiled run from its
// tiles (src/web/mesh_worker.rs), so the page only draws it; it holds the grid across jobs and
// is never stopped for a new run.
export class WorkerPool {
  constructor(app) {
    this.app = app;
    this.workers = []; // { worker, job: null | { run, index } }
    this.run = 0;
    this.mesher = null;
    this.meshBusy = false;
    this.meshesSent = 0;
    // Each finished job's worker time, for benchmarks: { kind, index | id, ms, at }.
    this.log = [];
  }

  // Hands the mesh worker the newest mesh job when it is free (the app keeps only the newest
  // waiting, so a later selection supersedes an earlier one).
  pumpMesh() {
    if (this.meshBusy) return;
    const job = this.app.takeMeshJob();
    if (!job) return;
    if (!this.mesher) this.mesher = this.spawnMesher();
    if (!this.mesher) {
      this.app.meshWorkerLost();
      this.app.meshFailed(job.id, 'this browser cannot start a Web Worker');
      return;
    }
    this.meshBusy = true;
    this.meshesSent++;
    const transfer = [job.kept.buffer, job.offsets.buffer];
    if (job.grid) transfer.push(job.grid.z.buffer);
    this.mesher.busyWith = job.id;
    this.mesher.postMessage({ kind: 'mesh', ...job }, transfer);
  }

  spawnMesher() {
    let worker;
    try {
      worker = new Worker(new URL('./pool-worker.js', import.meta.url), { type: 'module' });
    } catch {
      return null;
    }
    const lost = (message) => {
      worker.terminate();
      if (this.mesher === worker) this.mesher = null;
      this.meshBusy = false;
      this.app.meshWorkerLost();
      this.app.meshFailed(worker.busyWith ?? 0, message);
    };
    worker.onmessage = ({ data }) => {
      this.meshBusy = false;
      if (data.kind === 'mesh') {
        this.log.push({ kind: 'mesh', id: data.id, ms: data.ms, at: performance.now() });
        this.app.meshBuilt(data.id, data.kept, data.triangles, data.pointError, data.layers, data.maxError, data.toggles);
      } else {
        this.app.meshFailed(data.id, data.message);
      }
    };
    worker.onerror = (e) => {
      e.preventDefault();
      lost(e.message || 'the mesh worker stopped (its script did not load)');
    };
    worker.onmessageerror = () => lost('the mesh worker posted a message the page cannot read');
    return worker;
  }

  // Called once per animation frame: stops workers of a run left behind, hands out jobs.
  pump() {
    this.pumpMesh();
    const run = this.app.poolRunId();
    if (run !== this.run) {
      // A job cannot be interrupted inside its worker: the worker goes, a new one comes.
      for (const w of this.workers.filter((x) => x.job)) this.drop(w);
      this.run = run;
    }
    if (run === 0) return;
    const size = this.app.poolWorkers();
    for (;;) {
      let w = this.workers.find((x) => !x.job);
      if (!w && this.workers.length >= size) return;
      let job;
      try {
        job = this.app.takePoolJob();
      } catch (e) {
        // The job could not be cut (out of memory, say): the run stops with the reason.
        this.app.poolFailed(run, -1, e instanceof Error ? e.message : String(e));
        return;
      }
      if (!job) return;
      w ??= this.spawn();
      if (!w) {
        this.app.poolFailed(job.run, job.index, 'this browser cannot start a Web Worker');
        return;
      }
      w.job = { run: job.run, index: job.index };
      w.worker.postMessage(job, [job.surface.z.buffer]);
    }
  }

  spawn() {
    let worker;
    try {
      worker = new Worker(new URL('./pool-worker.js', import.meta.url), { type: 'module' });
    } catch {
      return null;
    }
    const w = { worker, job: null };
    const failed = (message) => {
      if (w.job) this.app.poolFailed(w.job.run, w.job.index, message);
      this.drop(w);
    };
    worker.onmessage = ({ data }) => {
      if (data.kind === 'front') {
        this.app.poolReport(data.run, data.index, data.scores, data.offsets, data.kept,
          data.evaluations, data.generation, data.done);
        if (data.done) w.job = null;
      } else if (data.kind === 'tile') {
        this.log.push({ kind: 'tile', index: data.index, ms: data.ms, bytes: data.front.length, at: performance.now() });
        this.app.poolReportTile(data.run, data.index, data.front);
        w.job = null;
      } else {
        failed(data.message);
      }
    };
    worker.onerror = (e) => {
      e.preventDefault();
      failed(e.message || 'the worker stopped (its script did not load)');
    };
    worker.onmessageerror = () => failed('the worker posted a message the page cannot read');
    this.workers.push(w);
    return w;
  }

  drop(w) {
    w.worker.terminate();
    this.workers = this.workers.filter((x) => x !== w);
  }
}
