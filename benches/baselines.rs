//! Run times of the classical baselines, on `tests/data/jacksboro_65x65` and on the 257×257
//! fbm terrain `fractal_257` of `scripts/terrain.py` (`tests/data/bunny_65x65` when run as a
//! test; see `common::large_grid`):
//!
//! - `greedy_max_error_1pct`: greedy insertion until E_max ≤ 1 % of the z range (the stopping
//!   rule of tools such as delatin, to compare with them);
//! - `greedy_max_error_all`, `greedy_sum_reduction_all`: greedy insertion of every point with
//!   each insertion rule (the sum-reduction rule, far slower, only on jacksboro_65x65);
//! - `decimation_to_50pct`: edge decimation from the full grid to its 50 % reduction;
//! - `score_triangulation`: re-scoring a mesh given as triangles
//!   ([`Evaluator::score_triangulation`]), which measures another tool's mesh with the project's
//!   ruler (here the canonical triangulation of 10 % of the grid).

mod common;

use common::{fixture, kept_subset, large_grid};
use criterion::{Criterion, criterion_group, criterion_main};
use paretomesh::baselines::{
    DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams, GreedyStop, InsertionRule,
};
use paretomesh::evaluator::Evaluator;
use paretomesh::optimizer::Optimizer;
use std::hint::black_box;
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    let grids = [
        ("jacksboro_65x65".to_string(), fixture("jacksboro_65x65")),
        large_grid(),
    ];
    for (name, hf) in grids {
        let hf = Arc::new(hf);
        // The sum-reduction rule runs on jacksboro_65x65 only (see above).
        let larger = name != "jacksboro_65x65";
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        let runs = [
            (
                "greedy_max_error_1pct",
                InsertionRule::MaxError,
                GreedyStop::MaxErrorFraction(0.01),
            ),
            (
                "greedy_max_error_all",
                InsertionRule::MaxError,
                GreedyStop::AllPoints,
            ),
            (
                "greedy_sum_reduction_all",
                InsertionRule::SumReduction,
                GreedyStop::AllPoints,
            ),
        ];
        for (label, rule, stop) in runs {
            if larger && rule == InsertionRule::SumReduction {
                continue;
            }
            let params = GreedyParams {
                rule,
                stop,
                ..GreedyParams::default()
            };
            group.bench_function(label, |b| {
                b.iter(|| {
                    let mut run = GreedyInsertion::new(hf.clone(), params.clone()).unwrap();
                    run.run_to_end()
                })
            });
        }
        group.bench_function("decimation_to_50pct", |b| {
            b.iter(|| {
                let mut run = EdgeDecimation::new(hf.clone(), DecimationParams::default()).unwrap();
                run.run_to_end()
            })
        });
        let mut ev = Evaluator::new(hf.clone());
        let kept = kept_subset(hf.len(), 0.1, 7, hf.corners());
        let triangles = ev.evaluate(&kept).unwrap().triangles;
        group.bench_function("score_triangulation", |b| {
            b.iter(|| black_box(ev.score_triangulation(black_box(&triangles)).unwrap()))
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
