//! Compare mode (`app/compare.rs`): every method shares the frame budget, each
//! reaches the front it reaches when run alone, and the live table holds exactly the numbers
//! the core metrics compute.

use crate::app::algorithms::{Params, build};
use crate::app::compare::{CompareRun, METHODS, TABLE_INTERVAL_MS};
use crate::app::state::Surface;
use crate::evaluator::Evaluator;
use crate::evolution::{Memetic, MemeticParams, Nsga2, WeightedSum, WeightedSumParams};
use crate::experiment::Method;
use crate::heightfield::Heightfield;
use crate::import::raw;
use crate::metrics::{
    self, DEFAULT_REFERENCE_POINT, Normalization, additive_epsilon, best_error_pick, coverage,
    fewest_triangles_pick, hypervolume_ratio, trade_off_pick,
};
use crate::optimizer::Optimizer;
use std::sync::Arc;

const GRID: &[u8] = include_bytes!("../../../tests/data/volcano_33x33.f32");
const SIDECAR: &[u8] = include_bytes!("../../../tests/data/volcano_33x33.json");

fn volcano() -> Surface {
    let hf = raw::parse(GRID, SIDECAR, "volcano_33x33").unwrap();
    Surface {
        name: "volcano_33x33".into(),
        heightfield: Arc::new(hf),
    }
}

// Small GA settings, so the weighted-sum GA's 11 runs finish quickly in a test; seed 5, not
// the default 1, so a seed that did not reach the GAs would show.
fn params() -> Params {
    Params {
        population: 8,
        generations: 3,
        seed: 5,
        ..Params::default()
    }
}

/// A clock that advances 1 ms per reading, so what a tick does is exact and repeatable.
fn ticking_clock() -> impl FnMut() -> f64 {
    let mut now = 0.0;
    move || {
        now += 1.0;
        now
    }
}

fn finished(surface: Surface, params: Params) -> CompareRun {
    let mut run = CompareRun::new(surface, params).unwrap();
    run.run();
    let mut clock = ticking_clock();
    let mut frames = 0;
    let mut finishing_ticks = 0;
    while run.is_running() {
        if run.tick(8.0, &mut clock).finished {
            finishing_ticks += 1;
        }
        frames += 1;
        assert!(frames < 1_000_000, "the comparison must finish");
    }
    assert!(frames > 1, "the comparison took several frames");
    assert_eq!(finishing_ticks, 1, "exactly the last tick reports the end");
    run
}

#[test]
fn a_finished_comparison_offers_the_trade_off_pick_of_the_merged_fronts() {
    let run = finished(volcano(), params());
    let all: Vec<_> = (0..METHODS.len())
        .flat_map(|k| run.front(k).unwrap().solutions().to_vec())
        .collect();
    let merged = crate::front::Front::merged(&all);
    let points: Vec<_> = merged.solutions().iter().map(|s| s.objectives()).collect();
    let expected = &merged.solutions()[trade_off_pick(&points, params().seed).unwrap().index];
    let pick = run.trade_off_solution().unwrap();
    assert_eq!(&pick, expected);
    // It is a member of some method's front, with its kept set, so the 3-D view can show it.
    assert!(all.contains(&pick));
    assert!(pick.kept.len() >= 4);
}

#[test]
fn each_method_reaches_the_front_it_reaches_alone() {
    let run = finished(volcano(), params());
    assert!(run.is_done());
    let hf = run.surface().heightfield.clone();
    for (k, method) in METHODS.into_iter().enumerate() {
        let mut alone = build(method.algorithm, &params(), hf.clone()).unwrap();
        alone.run_to_end();
        let front = run.front(k).unwrap();
        assert!(!front.is_empty(), "{method:?}");
        assert_eq!(front, alone.front(), "{method:?}");
        assert_eq!(
            run.status(k).unwrap().evaluations,
            alone.progress().evaluations,
            "{method:?}"
        );
    }
    // And against the core's GAs directly, as `paretomesh run --algo nsga2|weighted` builds
    // them with these parameters and seed.
    let p = params();
    let mut nsga2 = Nsga2::new(hf.clone(), p.ga(), p.seed).unwrap();
    nsga2.run_to_end();
    assert_eq!(run.front(0).unwrap(), nsga2.front());
    let weighted = WeightedSumParams {
        ga: p.ga(),
        ..WeightedSumParams::default()
    };
    let mut weighted = WeightedSum::new(hf.clone(), weighted, p.seed).unwrap();
    weighted.run_to_end();
    assert_eq!(run.front(1).unwrap(), weighted.front());
    // The weighted-sum front has at most one member per weight (11).
    assert!(run.front(1).unwrap().len() <= 11);
    // The memetic method runs with its own defaults and the form's seed, as `paretomesh run`
    // does without --algo.
    let mut memetic = Memetic::new(hf, MemeticParams::default(), p.seed).unwrap();
    memetic.run_to_end();
    assert_eq!(run.front(4).unwrap(), memetic.front());
}

#[test]
fn the_table_holds_the_numbers_the_core_metrics_compute() {
    let mut run = finished(volcano(), params());
    assert!(run.refresh_table(0.0));
    let table = run.table().unwrap().as_ref().unwrap().clone();
    assert!(table.complete);
    // The common normalisation: the corner-only mesh's E and the full grid's 2·32·32 triangles.
    let hf = run.surface().heightfield.clone();
    let n = Normalization::from_evaluator(&mut Evaluator::new(hf)).unwrap();
    assert_eq!(table.normalization, n);
    assert_eq!(n.t_scale(), 2048.0);
    assert_eq!(table.reference_point, DEFAULT_REFERENCE_POINT);
    let points: Vec<Vec<[f64; 2]>> = (0..5)
        .map(|k| n.solutions(run.front(k).unwrap().solutions()))
        .collect();
    let reference = metrics::merge(points.iter().map(Vec::as_slice)).unwrap();
    assert_eq!(table.reference_front_size, reference.len());
    assert_eq!(table.methods.len(), 5);
    for (k, row) in table.methods.iter().enumerate() {
        assert_eq!(row.method, METHODS[k]);
        assert!(row.done);
        let front = run.front(k).unwrap().solutions();
        assert_eq!(row.front_size, front.len());
        assert_eq!(row.evaluations, run.status(k).unwrap().evaluations);
        let hvr = hypervolume_ratio(&points[k], &reference, DEFAULT_REFERENCE_POINT).unwrap();
        assert_eq!(row.hvr, Some(hvr), "{:?}", row.method);
        assert!(hvr > 0.0 && hvr <= 1.0);
        let picks = row.picks.unwrap();
        let at = |i: usize| (front[i].e_sum, front[i].t);
        let best = at(best_error_pick(&points[k]).unwrap());
        let fewest = at(fewest_triangles_pick(&points[k]).unwrap());
        let trade = at(trade_off_pick(&points[k], params().seed).unwrap().index);
        assert_eq!((picks.best_error.e, picks.best_error.t), best);
        assert_eq!((picks.fewest_triangles.e, picks.fewest_triangles.t), fewest);
        assert_eq!((picks.trade_off.e, picks.trade_off.t), trade);
    }
    // Every ordered pair, A-major.
    assert_eq!(table.pairs.len(), 20);
    let mut row = table.pairs.iter();
    for (ka, a) in METHODS.into_iter().enumerate() {
        for (kb, b) in METHODS.into_iter().enumerate() {
            if a == b {
                continue;
            }
            let pair = row.next().unwrap();
            assert_eq!((pair.a, pair.b), (a, b));
            let eps = additive_epsilon(&points[ka], &points[kb]).unwrap();
            let c = coverage(&points[ka], &points[kb]).unwrap();
            assert_eq!(pair.epsilon, Some(eps), "{a:?} vs {b:?}");
            assert_eq!(pair.coverage, Some(c), "{a:?} vs {b:?}");
        }
    }
    // Indicator ranges: HVR in (0, 1] (checked above), C a share, and ε+(A, B) ≤ 0 exactly
    // when C(A, B) = 1 (every point of B weakly dominated by one of A).
    for p in &table.pairs {
        let (eps, c) = (p.epsilon.unwrap(), p.coverage.unwrap());
        assert!((0.0..=1.0).contains(&c), "{p:?}");
        assert_eq!(eps <= 0.0, c == 1.0, "{p:?}");
    }
}

#[test]
fn the_methods_share_the_frame_budget_and_take_turns() {
    let mut run = CompareRun::new(volcano(), params()).unwrap();
    // Paused: no work.
    let idle = run.tick(8.0, &mut ticking_clock());
    assert_eq!((idle.steps, idle.evaluations), (0, 0));
    run.run();
    // A budget for one slice only (every reading of this clock costs 1 ms): the first method
    // gets it and the others wait; the next frame starts with the next method.
    let mut clock = ticking_clock();
    let only = |k: usize| std::array::from_fn::<bool, { METHODS.len() }, _>(|i| i == k);
    let first = run.tick(1.0, &mut clock);
    assert_eq!(first.served, only(0));
    let second = run.tick(1.0, &mut clock);
    assert_eq!(second.served, only(1));
    // A generous budget serves every method in one frame.
    let all = run.tick(200.0, &mut clock);
    assert_eq!(all.served, [true; METHODS.len()]);
    for (k, method) in METHODS.into_iter().enumerate() {
        assert!(run.status(k).unwrap().evaluations > 0, "{method:?}");
    }
    // Run to the end: a finished method is never served again.
    let mut frames = 0;
    while run.is_running() {
        let done_before: Vec<bool> = (0..5).map(|k| run.status(k).unwrap().done).collect();
        let t = run.tick(8.0, &mut clock);
        for (k, method) in METHODS.into_iter().enumerate() {
            assert!(!(done_before[k] && t.served[k]), "{method:?}");
        }
        frames += 1;
        assert!(frames < 1_000_000);
    }
    assert!(run.is_done());
    // Pausing and resuming a finished run does nothing.
    run.pause();
    run.run();
    assert!(!run.is_running());
}

#[test]
fn the_live_table_is_throttled_but_final_when_the_run_ends() {
    let mut run = CompareRun::new(volcano(), params()).unwrap();
    // Before anything ran, NSGA-II has no front yet (its first unit is one evaluation): its row
    // and every pair with it are empty, not an error.
    assert!(run.refresh_table(1000.0));
    let early = run.table().unwrap().as_ref().unwrap().clone();
    assert_eq!(early.methods[0].front_size, 0);
    for m in &early.methods {
        assert_eq!(m.hvr.is_some(), m.front_size > 0, "{:?}", m.method);
        assert_eq!(m.picks.is_some(), m.front_size > 0, "{:?}", m.method);
    }
    assert_eq!(early.pairs.len(), 20);
    for p in &early.pairs {
        let present = |x: Method| {
            early
                .methods
                .iter()
                .any(|m| m.method == x && m.front_size > 0)
        };
        assert_eq!(p.epsilon.is_some(), present(p.a) && present(p.b), "{p:?}");
    }
    // Nothing changed: no recomputation, however late.
    assert!(!run.refresh_table(9000.0));
    run.run();
    let mut clock = ticking_clock();
    while run.front(0).unwrap().is_empty() {
        run.tick(8.0, &mut clock);
    }
    // Changed, but too soon after the last one.
    assert!(!run.refresh_table(1000.0 + TABLE_INTERVAL_MS / 2.0));
    assert!(run.refresh_table(1000.0 + TABLE_INTERVAL_MS));
    // A partial table: the methods with a front so far have numbers.
    let partial = run.table().unwrap().as_ref().unwrap().clone();
    assert!(!partial.complete);
    assert!(partial.methods[0].hvr.is_some());
    for m in &partial.methods {
        assert_eq!(m.hvr.is_some(), m.front_size > 0, "{:?}", m.method);
    }
    // Once every method is done, the next refresh is immediate and final.
    while run.is_running() {
        run.tick(8.0, &mut clock);
    }
    assert!(run.refresh_table(1000.0 + TABLE_INTERVAL_MS + 1.0));
    let last = run.table().unwrap().as_ref().unwrap();
    assert!(last.complete);
    assert!(
        last.pairs
            .iter()
            .all(|p| p.epsilon.is_some() && p.coverage.is_some())
    );
}

#[test]
fn bad_parameters_and_a_flat_surface_are_messages_not_panics() {
    let mut bad = params();
    bad.crossover_probability = 2.0;
    let e = CompareRun::new(volcano(), bad).err().unwrap();
    assert!(e.contains("crossover probability"), "{e}");
    // A plane: the corner-only mesh is exact, so E cannot be normalised by its error. The runs
    // still work; the table says why it has no numbers.
    let plane = Heightfield::new(9, 9, (0..81).map(|i| (i % 9) as f64 * 0.5).collect()).unwrap();
    let flat = Surface {
        name: "plane".into(),
        heightfield: Arc::new(plane),
    };
    let mut run = finished(flat, params());
    assert!(run.refresh_table(0.0));
    let message = run.table().unwrap().as_ref().err().unwrap().clone();
    assert!(message.contains("normalisation"), "{message}");
    assert!((0..5).all(|k| !run.front(k).unwrap().is_empty()));
    assert_eq!(
        run.methods().collect::<Vec<_>>(),
        vec![
            Method::NSGA2,
            Method::WEIGHTED,
            Method::DECIMATION,
            Method::GREEDY,
            Method::MEMETIC
        ]
    );
}
