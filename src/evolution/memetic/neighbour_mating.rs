//! Mating among neighbours in T: a parent's mate is one of the population members nearest to
//! it in triangle count, since a child of a sparse and a dense mesh is too dense on one side and
//! too sparse on the other. The crossover is a straight cut: the child keeps one parent's points
//! on one side of a random grid line and the other's beyond it, which keeps each parent's
//! spacing of points where it is taken from.

use super::member::Member;
use crate::evaluator::{Evaluator, MeshState};
use crate::heightfield::Heightfield;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;

/// A mate is drawn among this many members nearest in T.
pub(crate) const NEIGHBOURS: usize = 4;

/// Draws the mate of `population[a]`: one of the [`NEIGHBOURS`] other members nearest to it in
/// T (ties to the smaller index). `None` for a population of one.
pub(crate) fn pick_mate(population: &[Member], a: usize, rng: &mut Pcg64Mcg) -> Option<usize> {
    let t = population[a].score.t;
    let mut others: Vec<usize> = (0..population.len()).filter(|&i| i != a).collect();
    if others.is_empty() {
        return None;
    }
    others.sort_by_key(|&i| (population[i].score.t.abs_diff(t), i));
    let k = others.len().min(NEIGHBOURS);
    Some(others[rng.random_range(0..k)])
}

/// Draws the mate of `population[a]` among all other members, equally likely, whatever their
/// T (the ablation of mating among neighbours). `None` for a population of one.
pub(crate) fn pick_any_mate(population: &[Member], a: usize, rng: &mut Pcg64Mcg) -> Option<usize> {
    let n = population.len();
    if n < 2 {
        return None;
    }
    // Draw among the n − 1 others by skipping over `a`.
    let b = rng.random_range(0..n - 1);
    Some(if b >= a { b + 1 } else { b })
}

/// A cut: grid points with coordinate ≥ `at` along the axis come from the second parent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Cut {
    /// Cut across x (columns) when true, across y (rows) otherwise.
    pub vertical: bool,
    /// The first column (or row) taken from the second parent, in 1..side.
    pub at: usize,
}

impl Cut {
    /// A random cut through the inside of the grid.
    pub(crate) fn draw(hf: &Heightfield, rng: &mut Pcg64Mcg) -> Self {
        let vertical = rng.random::<bool>();
        let side = if vertical { hf.width() } else { hf.height() };
        Self {
            vertical,
            at: rng.random_range(1..side.max(2)),
        }
    }

    /// The grid points beyond the cut as a bitset (bit `i` of word `i / 64`), what
    /// [`Evaluator::compose`] reads: set a run of bits per row (or one run for a cut across
    /// rows), so it costs a bit per grid point, not a test.
    pub(crate) fn labels(&self, hf: &Heightfield) -> Vec<u64> {
        let (w, n) = (hf.width(), hf.len());
        let mut bits = vec![0u64; n.div_ceil(64)];
        // Bits from..to: single bits up to a word boundary, whole words, single bits after.
        let mut set = |from: usize, to: usize| {
            let mut i = from;
            while i < to && !i.is_multiple_of(64) {
                bits[i / 64] |= 1 << (i % 64);
                i += 1;
            }
            while i + 64 <= to {
                bits[i / 64] = u64::MAX;
                i += 64;
            }
            while i < to {
                bits[i / 64] |= 1 << (i % 64);
                i += 1;
            }
        };
        if self.vertical {
            for y in 0..hf.height() {
                set(y * w + self.at.min(w), (y + 1) * w);
            }
        } else {
            set((self.at * w).min(n), n);
        }
        bits
    }

    /// Is grid point `i` beyond the cut (taken from the second parent)?
    pub(crate) fn is_from_second(&self, hf: &Heightfield, i: u32) -> bool {
        let (x, y) = hf.coords(i);
        (if self.vertical { x } else { y }) >= self.at
    }
}

/// The child of `a` and `b` across `cut`, scored: its mesh is composed from both parents'
/// ([`Evaluator::compose`]) when it can be, else built; one evaluation either way, the same
/// bits. Fills the parents' disc boxes.
pub(crate) fn cross(evaluator: &mut Evaluator, a: &mut Member, b: &mut Member, cut: Cut) -> Member {
    let hf = evaluator.heightfield().clone();
    let mut kept: Vec<u32> = a
        .kept
        .iter()
        .copied()
        .filter(|&i| !cut.is_from_second(&hf, i))
        .chain(
            b.kept
                .iter()
                .copied()
                .filter(|&i| cut.is_from_second(&hf, i)),
        )
        .collect();
    kept.sort_unstable();
    kept.dedup();
    let from_b = cut.labels(&hf);
    a.state.ensure_disc_boxes();
    b.state.ensure_disc_boxes();
    let mut state = MeshState::default();
    match evaluator.compose(&mut state, &a.state, &b.state, &from_b) {
        Some(score) => Member::scored(kept, score, state),
        None => Member::fresh(evaluator, kept),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bitset of a cut marks exactly the points beyond it, for cuts of either direction at
    /// every position (words split anywhere by the rows).
    #[test]
    fn a_cuts_labels_are_the_points_beyond_it() {
        for (w, h) in [(5usize, 7usize), (64, 3), (67, 9), (130, 2)] {
            let hf = Heightfield::new(w, h, vec![0.0; w * h]).unwrap();
            for vertical in [false, true] {
                let side = if vertical { w } else { h };
                for at in 1..side {
                    let cut = Cut { vertical, at };
                    let bits = cut.labels(&hf);
                    assert_eq!(bits.len(), (w * h).div_ceil(64));
                    for i in 0..(w * h) as u32 {
                        let bit = (bits[i as usize / 64] >> (i % 64)) & 1 == 1;
                        assert_eq!(bit, cut.is_from_second(&hf, i), "{w}x{h} {cut:?} point {i}");
                    }
                    // No bit past the grid.
                    let tail = (w * h) % 64;
                    if tail != 0 {
                        assert_eq!(bits[bits.len() - 1] >> tail, 0);
                    }
                }
            }
        }
    }
}
