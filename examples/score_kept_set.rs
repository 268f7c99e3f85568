//! Load a grid, score a kept set of its points, and read the mesh the score was measured on.
//!
//! ```text
//! cargo run --release --example score_kept_set [GRID]
//! ```
//!
//! GRID is any surface the command line reads (default `tests/data/jacksboro_33x33.f32`).

use paretomesh::evaluator::Evaluator;
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use std::path::PathBuf;
use std::sync::Arc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args_os().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/jacksboro_33x33.f32"),
        PathBuf::from,
    );
    let hf = Arc::new(import::load(&path)?);
    let (lo, hi) = hf.z_range();
    println!(
        "{}: {}×{} points, z from {lo} to {hi}",
        path.display(),
        hf.width(),
        hf.height()
    );

    // A kept set is a list of grid indices (y·W + x). The evaluator always adds the four
    // corners, so the mesh covers the whole grid.
    let mut ev = Evaluator::new(hf.clone());
    for step in [16, 8, 4] {
        let kept: Vec<u32> = (0..hf.height())
            .step_by(step)
            .flat_map(|y| (0..hf.width()).step_by(step).map(move |x| (x, y)))
            .map(|(x, y)| hf.index(x, y))
            .collect();
        let score = ev.score(&kept)?;
        println!(
            "every {step:>2}th point of every {step:>2}th row: T = {:>4}, E = {:.1} (max {:.2}, RMS {:.3})",
            score.t, score.e_sum, score.e_max, score.rms
        );
    }

    // `evaluate` also returns the triangles (grid-index triples, counter-clockwise) of the
    // kept set's canonical Delaunay triangulation: the same kept set always gives the same
    // triangles.
    let kept = [hf.index(hf.width() / 2, hf.height() / 2)];
    let evaluation = ev.evaluate(&kept)?;
    println!(
        "the centre point alone: T = {}, triangles {:?}",
        evaluation.score.t, evaluation.triangles
    );

    // A height field can also be made from your own heights.
    let (w, h) = (9, 5);
    let z = (0..w * h).map(|i| ((i % w) * (i / w)) as f64).collect();
    let saddle = Arc::new(Heightfield::new(w, h, z)?);
    let score = Evaluator::new(saddle).score(&[])?;
    println!(
        "a 9×5 saddle, corners only: T = {}, E = {}",
        score.t, score.e_sum
    );

    // Bad input is an error, never a panic.
    if let Err(e) = ev.score(&[u32::MAX]) {
        println!("an index outside the grid: {e}");
    }
    Ok(())
}
