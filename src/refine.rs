//! Exact triangle budgets: a front member refined up to a budget by greedy insertion of its
//! worst points, each step scored exactly.
//!
//! A front has members at some triangle counts only. When a user asks for at most N triangles
//! and the nearest member below N has far fewer, the mesh is grown from that member: each step
//! inserts the grid point of largest vertical error (the worst point in E_sum, RMS and E_max
//! alike) into its canonical Delaunay mesh, as greedy insertion does, until the mesh has at
//! least [`budget_floor`]`(N)` triangles. Inserting an interior point adds two triangles and a
//! point on the grid's border one, so the step that would pass N is never taken.

use crate::baselines::{GreedyInsertion, GreedyParams};
use crate::evaluator::Score;
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use std::sync::Arc;

/// The fewest triangles an export for a budget of `n` aims at: ⌈0.99·n⌉.
pub fn budget_floor(n: usize) -> usize {
    n - n / 100
}

/// A mesh grown from a member to a triangle budget.
#[derive(Clone, Debug, PartialEq)]
pub struct Refined {
    /// Its kept grid indices, increasing, corners included.
    pub kept: Vec<u32>,
    /// Its score, bit for bit a fresh [`Evaluator::score`](crate::evaluator::Evaluator::score)
    /// of `kept`.
    pub score: Score,
    /// Points inserted into the member's mesh.
    pub insertions: usize,
}

/// Grows the mesh of `kept` on `hf` by inserting its worst point, one at a time, until it has
/// at least [`budget_floor`]`(max_t)` triangles, never more than `max_t`; it stops early when
/// every grid point is kept, or when the next worst point is interior (two more triangles) and
/// only one is left under `max_t`. Errors: an index off the grid.
pub fn refine_to_budget(
    hf: Arc<Heightfield>,
    kept: &[u32],
    max_t: usize,
) -> Result<Refined, String> {
    let floor = budget_floor(max_t);
    let (w, h) = (hf.width() as u32, hf.height() as u32);
    let on_border = |i: u32| {
        let (x, y) = (i % w, i / w);
        x == 0 || y == 0 || x + 1 == w || y + 1 == h
    };
    let mut run =
        GreedyInsertion::from_kept(hf, GreedyParams::default(), kept).map_err(|e| e.to_string())?;
    let mut insertions = 0;
    while run.triangle_count() < floor {
        let Some(next) = run.worst_point() else {
            break;
        };
        let grows = if on_border(next) { 1 } else { 2 };
        if run.triangle_count() + grows > max_t {
            break;
        }
        run.unit();
        insertions += 1;
    }
    Ok(Refined {
        kept: run.kept(),
        score: run.score(),
        insertions,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::Evaluator;

    /// A rough, deterministic terrain: waves plus hashed noise.
    fn terrain(w: usize, h: usize, seed: u64) -> Heightfield {
        let z = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                let mut n = (i as u64 ^ seed).wrapping_mul(0x9e37_79b9_7f4a_7c15);
                n ^= n >> 29;
                (x * 0.21).sin() * 5.0 + (y * 0.13).cos() * 3.0 + (n % 1000) as f64 / 1000.0
            })
            .collect();
        Heightfield::new(w, h, z).unwrap()
    }

    #[test]
    fn the_refined_mesh_is_within_the_budget_and_scored_exactly() {
        let hf = Arc::new(terrain(33, 29, 5));
        let mut ev = Evaluator::new(hf.clone());
        let start: Vec<u32> = vec![0, 32, 28 * 33, 29 * 33 - 1, 5 * 33 + 7, 20 * 33 + 11];
        let from = ev.score(&start).unwrap();
        for max_t in [from.t, from.t + 1, 101, 400, 997] {
            let r = refine_to_budget(hf.clone(), &start, max_t).unwrap();
            let fresh = ev.score(&r.kept).unwrap();
            assert_eq!(r.score, fresh, "max_t {max_t}");
            assert!(r.score.t <= max_t, "{} > {max_t}", r.score.t);
            // Below the floor only when one interior point more would pass the budget.
            assert!(r.score.t >= budget_floor(max_t) || r.score.t + 1 == max_t);
            assert!(start.iter().all(|i| r.kept.binary_search(i).is_ok()));
            assert_eq!(r.kept.len(), start.len() + r.insertions);
        }
        // A budget at the member's own T inserts nothing.
        let same = refine_to_budget(hf.clone(), &start, from.t).unwrap();
        assert_eq!((same.insertions, same.score), (0, from));
    }

    #[test]
    fn floors_are_ninety_nine_percent_rounded_up() {
        assert_eq!(budget_floor(2), 2);
        assert_eq!(budget_floor(100), 99);
        assert_eq!(budget_floor(209_715), 207_618);
        for n in 2..5000 {
            let f = budget_floor(n);
            assert!(f as f64 >= 0.99 * n as f64 && (f as f64 - 1.0) < 0.99 * n as f64);
        }
    }
}
