//! NSGA-II end to end on a fixture in tests/data (always present): population 100, 5
//! generations on jacksboro_33x33. Where the time goes is a matter for a profiler (`perf record
//! ./target/release/paretomesh run …`): nearly all of it is in the evaluator.
//!
//! The full paper run (pop 100, 50 generations on jacksboro_65x65) takes ≈6 s of CPU with
//! incremental scoring (≈18 s before; see the README's "Speed"); measure it with
//! `paretomesh run` (it prints evaluations per second).

use criterion::{Criterion, criterion_group, criterion_main};
use paretomesh::evolution::{GaParams, Nsga2};
use paretomesh::heightfield;
use paretomesh::optimizer::Optimizer;
use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/jacksboro_33x33.f32");
    let hf = Arc::new(heightfield::load(&path).expect("fixture"));
    let params = GaParams {
        population: 100,
        generations: 5,
        ..GaParams::default()
    };
    let mut group = c.benchmark_group("jacksboro_33x33");
    group.sample_size(10);
    group.bench_function("nsga2_pop100_gens5", |b| {
        b.iter(|| {
            let mut opt = Nsga2::new(hf.clone(), params.clone(), 1).unwrap();
            black_box(opt.run_to_end())
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
