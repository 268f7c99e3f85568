//! The foundation issue's speed target as one number per density: a fresh evaluation's time over
//! spade's bare bulk load of the same points (target ≤ 1.3), measured **interleaved** (release
//! build recommended):
//!
//! ```text
//! cargo run --release --example evaluator_ratio -- GRID.f32 [REPEATS]
//! ```
//!
//! Why beside `cargo bench --bench evaluator`: criterion measures spade and the evaluator
//! seconds apart, and on a shared VM whose speed drifts by a third within minutes their ratio
//! moved between 1.0 and 1.45 for the same code. Here each repeat times one bulk load and then
//! one evaluation of the same kept set (2 %, 10 % and 30 % of the grid, chosen as the bench
//! chooses them), so both see the same moment of the machine; the ratio is given at the
//! minimum, the first quartile and the median of each.

use paretomesh::evaluator::Evaluator;
use paretomesh::heightfield;
use rand::{RngExt, SeedableRng};
use spade::{DelaunayTriangulation, Point2, Triangulation};
use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        return Err("usage: evaluator_ratio GRID.f32 [REPEATS]".into());
    };
    let repeats: usize = match args.get(1) {
        Some(r) => r.parse()?,
        None => 500,
    };
    let hf = heightfield::load(std::path::Path::new(path))?;
    let w = hf.width() as u32;
    let mut evaluator = Evaluator::new(Arc::new(hf.clone()));
    for percent in [2u32, 10, 30] {
        // The bench's kept set: the same seed and draw, plus the corners.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        let mut kept: Vec<u32> = (0..hf.len() as u32)
            .filter(|_| rng.random::<f64>() < percent as f64 / 100.0)
            .collect();
        kept.extend(hf.corners());
        kept.sort_unstable();
        kept.dedup();
        let points: Vec<Point2<f64>> = kept
            .iter()
            .map(|&i| Point2::new((i % w) as f64, (i / w) as f64))
            .collect();
        let (mut spade_us, mut evaluate_us) = (Vec::new(), Vec::new());
        for _ in 0..repeats {
            let start = Instant::now();
            let t = DelaunayTriangulation::<Point2<f64>>::bulk_load(black_box(points.clone()))?;
            black_box(t.num_inner_faces());
            spade_us.push(start.elapsed().as_secs_f64() * 1e6);
            let start = Instant::now();
            black_box(evaluator.score(black_box(&kept))?);
            evaluate_us.push(start.elapsed().as_secs_f64() * 1e6);
        }
        spade_us.sort_by(f64::total_cmp);
        evaluate_us.sort_by(f64::total_cmp);
        let at = |v: &[f64], q: f64| v[(q * (v.len() - 1) as f64) as usize];
        let column = |q: f64| {
            let (s, e) = (at(&spade_us, q), at(&evaluate_us, q));
            format!("{s:>8.0} {e:>8.0} {:>6.3}", e / s)
        };
        println!(
            "{percent:>2} % ({} points)  spade / evaluate µs / ratio:  min {}  p25 {}  median {}",
            kept.len(),
            column(0.0),
            column(0.25),
            column(0.5)
        );
    }
    Ok(())
}
