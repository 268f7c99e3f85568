//! Run NSGA-II (the source paper's method) step by step, as the browser app does between frames,
//! then greedy insertion on the same grid, and compare their fronts.
//!
//! ```text
//! cargo run --release --example run_optimizer [GRID]
//! ```
//!
//! GRID defaults to `tests/data/bunny_33x33.f32`.

use paretomesh::baselines::{GreedyInsertion, GreedyParams};
use paretomesh::evolution::{GaParams, Nsga2};
use paretomesh::front::Front;
use paretomesh::import;
use paretomesh::optimizer::Optimizer;
use std::path::PathBuf;
use std::sync::Arc;

/// The smallest E on `front` with at most `t` triangles.
fn best_within(front: &Front, t: usize) -> Option<f64> {
    let within = front.solutions().iter().filter(|s| s.t <= t);
    within.map(|s| s.e_sum).reduce(f64::min)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args_os().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/bunny_33x33.f32"),
        PathBuf::from,
    );
    let hf = Arc::new(import::load(&path)?);

    // The paper's settings with a smaller budget. The seed fixes the run: the same seed gives
    // the same front however the run is sliced into steps.
    let params = GaParams {
        population: 60,
        generations: 20,
        ..GaParams::default()
    };
    let mut nsga2 = Nsga2::new(hf.clone(), params, 1)?;
    loop {
        // At least 2 000 more evaluations per step (whole units of work).
        let progress = nsga2.step(2_000);
        println!(
            "generation {:>2}: {:>5} evaluations, {} solutions on the front",
            progress.generation,
            progress.evaluations,
            nsga2.front().len()
        );
        if progress.done {
            break;
        }
    }

    // Every method implements the same trait, so a baseline runs the same way.
    let mut greedy = GreedyInsertion::new(hf.clone(), GreedyParams::default())?;
    let progress = greedy.run_to_end();
    println!(
        "greedy insertion: {} evaluations, {} solutions on the front",
        progress.evaluations,
        greedy.front().len()
    );

    let full = hf.full_triangles();
    println!("best E within a share of the full grid's {full} triangles:");
    let show = |e: Option<f64>| e.map_or("-".to_string(), |e| format!("{e:.2}"));
    for percent in [5, 10, 20, 40] {
        let t = full * percent / 100;
        println!(
            "  T ≤ {t:>4} ({percent:>2} %): NSGA-II {:>8}, greedy insertion {:>8}",
            show(best_within(nsga2.front(), t)),
            show(best_within(greedy.front(), t))
        );
    }
    Ok(())
}
