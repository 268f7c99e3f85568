//! NSGA-II end to end on fixtures in tests/data:
//!
//! - `jacksboro_33x33/nsga2_pop100_gens5`: population 100, 5 generations, a quick check;
//! - `jacksboro_65x65/nsga2_paper_run`: a full paper run (population 100, 50 generations, OAX,
//!   p_c = 0.8, p_m = 1/L, seed 1) on one core. `paretomesh run tests/data/jacksboro_65x65.f32
//!   --algo nsga2 --seed 1` times the same run (its `done:` line, with evaluations per second).
//!
//! Where the time goes is a matter for a profiler (`perf record -e cpu-clock -g
//! ./target/release/paretomesh run …`): nearly all of it is in the evaluator's scoring of OAX
//! rows and their mutants (see docs/performance.md).

mod common;

use criterion::{Criterion, criterion_group, criterion_main};
use paretomesh::evolution::{GaParams, Nsga2};
use paretomesh::optimizer::Optimizer;
use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

/// Times NSGA-II from construction to its last generation on fixture `name` (seed 1).
fn bench_run(c: &mut Criterion, name: &str, id: &str, params: GaParams) {
    let hf = Arc::new(common::fixture(name));
    let mut group = c.benchmark_group(name);
    // Ten samples in 10 s: the paper run takes about 0.8 s.
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    group.bench_function(id, |b| {
        b.iter(|| {
            let mut opt = Nsga2::new(hf.clone(), params.clone(), 1).unwrap();
            black_box(opt.run_to_end())
        })
    });
    group.finish();
}

fn bench(c: &mut Criterion) {
    let quick = GaParams {
        population: 100,
        generations: 5,
        ..GaParams::default()
    };
    bench_run(c, "jacksboro_33x33", "nsga2_pop100_gens5", quick);
    // The paper's defaults: population 100, 50 generations, crossover 0.8, mutation 1/L.
    bench_run(c, "jacksboro_65x65", "nsga2_paper_run", GaParams::default());
}

criterion_group!(benches, bench);
criterion_main!(benches);
