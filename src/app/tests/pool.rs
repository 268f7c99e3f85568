//! The app's runs in a pool of Web Workers, natively: the page's side of the protocol driven by
//! "workers" that run their jobs here, as `www/pool-worker.js` does in a browser. Native only:
//! the CLI's tiled run it compares with runs threads.
#![cfg(not(target_arch = "wasm32"))]

use crate::app::algorithms::{self, Algorithm, Params};
use crate::app::pool::{FrontParts, PoolSetup, Work};
use crate::app::state::{App, RunConfig, Surface};
use crate::heightfield::Heightfield;
use crate::optimizer::Progress;
use crate::tiling::{run_tile, run_tiled};
use std::sync::Arc;

fn terrain(w: usize, h: usize) -> Heightfield {
    let z = (0..w * h)
        .map(|i| ((i % w) as f64 * 0.3).sin() * 4.0 + ((i / w) as f64 * 0.2).cos() * 3.0)
        .collect();
    Heightfield::new(w, h, z).unwrap()
}

fn app(hf: Heightfield, setup: PoolSetup) -> App {
    let mut app = App::new(
        Surface {
            name: "terrain".to_string(),
            heightfield: Arc::new(hf),
        },
        RunConfig {
            algorithm: Algorithm::Nsga2,
            params: Params {
                population: 8,
                generations: 3,
                seed: 6,
                ..Params::default()
            },
            budget_ms: 8.0,
        },
    );
    app.set_pool_setup(setup);
    app
}

/// A clock that advances 1 ms per reading.
fn clock() -> impl FnMut() -> f64 {
    let mut now = 0.0;
    move || {
        now += 1.0;
        now
    }
}

#[test]
fn an_untiled_run_in_a_worker_reaches_the_front_of_a_run_on_the_page() {
    let hf = terrain(30, 20);
    let setup = PoolSetup {
        always: true,
        ..PoolSetup::default()
    };
    let mut app = app(hf.clone(), setup);
    app.run().unwrap();
    let pool = app.pool_run().expect("the run went to the pool");
    let job = pool.next_job().unwrap();
    assert!(pool.next_job().is_none(), "one job for an untiled grid");
    let Work::Whole { algorithm, params } = job.work else {
        panic!("an untiled job runs the whole grid");
    };
    // The page's frame does no work and does not spin while the worker runs.
    let report = app.tick(8.0, &mut clock());
    assert_eq!((report.steps, report.evaluations), (1, 0));

    // The worker: the algorithm on the grid, posting its front part-way and at the end.
    let mut optimizer = algorithms::build(algorithm, &params, Arc::new(hf.clone())).unwrap();
    let p = optimizer.step(50);
    let parts = FrontParts::of(optimizer.front());
    app.pool_report(job.run, 0, parts.into_front().unwrap(), p)
        .unwrap();
    assert_eq!(app.front().unwrap(), optimizer.front());
    assert!(app.is_running() && app.selected().is_none());
    let end = optimizer.run_to_end();
    let front = FrontParts::of(optimizer.front()).into_front().unwrap();
    app.pool_report(job.run, 0, front, end).unwrap();

    let mut page = algorithms::build(algorithm, &params, Arc::new(hf)).unwrap();
    page.run_to_end();
    assert_eq!(
        app.front().unwrap(),
        page.front(),
        "the same front as on the page"
    );
    assert!(app.status().done && !app.is_running());
    assert!(
        app.selected().is_some(),
        "the trade-off pick is selected at the end"
    );
    let mesh = app.selected_mesh(None).unwrap().unwrap();
    assert_eq!(mesh.triangles.len(), app.selected().unwrap().t);
}

#[test]
fn a_tiled_grid_runs_in_the_pool_to_the_clis_tiled_front() {
    let hf = terrain(70, 40);
    let setup = PoolSetup {
        workers: 2,
        always: false,
        tile: 36,
    };
    let mut app = app(hf.clone(), setup);
    assert!(
        app.step_once().unwrap_err().contains("Web Workers"),
        "a tiled grid does not step on the page"
    );
    app.run().unwrap();
    let pool = app.pool_run().expect("a tiled grid goes to the pool");
    let plan = pool.tiled().unwrap().plan().clone();
    let jobs: Vec<_> = std::iter::from_fn(|| pool.next_job()).collect();
    assert_eq!(jobs.len(), 2 * plan.len());
    // Two workers finish their jobs out of order; each job runs on its tile alone.
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.swap(0, 1);
    order[plan.len()..].reverse();
    for &i in &order {
        let Work::Tile(job) = &jobs[i].work else {
            panic!("a tiled run's jobs are tiles");
        };
        let tile_hf = plan.cut(&hf, job.tile).unwrap();
        let front = run_tile(&tile_hf, &plan, job.tile, &job.config, job.seed).unwrap();
        app.pool_report_tile(jobs[i].run, i, front).unwrap();
        if i == order[plan.len() - 1] {
            assert!(
                !app.front().unwrap().is_empty(),
                "a whole-grid front after the first pass"
            );
        }
    }
    assert!(app.status().done);
    let params = app.config().params.clone();
    let cli = run_tiled(
        &hf,
        &plan,
        &algorithms::config(Algorithm::Nsga2, &params),
        params.seed,
        1,
    )
    .unwrap();
    let front = app.front().unwrap();
    let objectives: Vec<_> = front
        .solutions()
        .iter()
        .map(|s| (s.e_sum, s.e_max, s.t as u64))
        .collect();
    let expected: Vec<_> = cli
        .members
        .iter()
        .map(|m| (m.e_sum, m.e_max, m.t))
        .collect();
    assert_eq!(objectives, expected, "the CLI's tiled front");
    let selected = app.selected().expect("the trade-off pick").clone();
    let mesh = app.selected_mesh(None).unwrap().unwrap();
    assert_eq!(
        mesh.triangles.len(),
        selected.t,
        "the member's mesh, rebuilt from its tiles"
    );
    // Drawn with at most a few triangles, the view shows a coarser member of the same front.
    let coarse = app.selected_mesh(Some(selected.t - 1)).unwrap().unwrap();
    assert!(coarse.triangles.len() < selected.t);
    assert!(
        front
            .solutions()
            .iter()
            .any(|s| s.t == coarse.triangles.len())
    );
}

#[test]
fn a_failed_worker_stops_the_run_and_run_starts_afresh() {
    let mut first_app = app(
        terrain(30, 20),
        PoolSetup {
            always: true,
            ..PoolSetup::default()
        },
    );
    first_app.run().unwrap();
    let first = first_app.pool_run().unwrap().id();
    first_app.pool_failed(first, Some(0), "out of memory");
    assert!(!first_app.is_running() && first_app.status().done);
    assert!(
        first_app
            .pool_run()
            .unwrap()
            .failure()
            .unwrap()
            .contains("out of memory")
    );
    // A late report of the failed run changes nothing.
    let late = Progress {
        evaluations: 1,
        generation: 0,
        done: true,
    };
    first_app
        .pool_report(first, 0, Default::default(), late)
        .unwrap();
    assert!(first_app.front().unwrap().is_empty());
    first_app.run().unwrap();
    let second = first_app.pool_run().unwrap();
    assert!(second.id() > first && second.failure().is_none());
    // A bad tile size is refused before any work.
    let mut bad = app(
        terrain(70, 40),
        PoolSetup {
            workers: 1,
            always: false,
            tile: 8,
        },
    );
    assert!(bad.run().unwrap_err().contains("too small"));
}
