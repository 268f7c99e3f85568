//! Run times of the classical baselines: greedy insertion down to E_max ≤ 1 % of the z range
//! (the target, to compare with the npm `delatin` package), greedy insertion of every
//! point with both rules, and edge decimation to its 50 % reduction.
//!
//! Reads `jacksboro_65x65` and `camera_257x257` from `../shared/data` (or `$PARETOMESH_DATA`);
//! says so and skips a grid when it is absent.

use criterion::{Criterion, criterion_group, criterion_main};
use paretomesh::baselines::{
    DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams, GreedyStop, InsertionRule,
};
use paretomesh::{heightfield, optimizer::Optimizer};
use std::path::PathBuf;
use std::sync::Arc;

fn data_dir() -> PathBuf {
    std::env::var_os("PARETOMESH_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"))
}

fn bench(c: &mut Criterion) {
    for name in ["jacksboro_65x65", "camera_257x257"] {
        let path = data_dir().join(format!("{name}.f32"));
        let hf = match heightfield::load(&path) {
            Ok(hf) => Arc::new(hf),
            Err(e) => {
                eprintln!("skipping {name}: {e} (shared data absent?)");
                continue;
            }
        };
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
            if name.starts_with("camera") && rule == InsertionRule::SumReduction {
                continue; // about 20 s a run: measured once with the timing example instead.
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
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
