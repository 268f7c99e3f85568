// The pool of Web Workers that runs the app's pool runs (src/app/pool.rs), one worker per core.
// The app says which run is under way and hands out its jobs; this file starts workers, passes
// jobs and fronts between them and the app, and stops the workers of a run the app has left
// (reset, another surface, a failed worker). No SharedArrayBuffer: jobs and fronts travel by
// postMessage with transferables, so the app works from any static server.
export class WorkerPool {
  constructor(app) {
    this.app = app;
    this.workers = []; // { worker, job: null | { run, index } }
    this.run = 0;
  }

  // Called once per animation frame: stops workers of a run left behind, hands out jobs.
  pump() {
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
