//! Objectives of an evaluated chromosome, the normalised weighted sum used wherever a scalar
//! fitness is needed, and the scorer that turns chromosomes into objectives and counts the
//! evaluations.

use super::chromosome::Chromosome;
use crate::evaluator::Evaluator;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What the [`Evaluator`] says about one kept set.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Objectives {
    /// E = Σ |z − z̃|.
    #[serde(rename = "E_sum")]
    pub e_sum: f64,
    /// max |z − z̃|.
    #[serde(rename = "E_max")]
    pub e_max: f64,
    /// Triangle count.
    #[serde(rename = "T")]
    pub t: usize,
}

impl Objectives {
    /// The minimised pair (E_sum, T).
    pub fn pair(&self) -> [f64; 2] {
        [self.e_sum, self.t as f64]
    }
}

/// F = w·E/E₀ + (1 − w)·T/T₀, to minimise.
///
/// Normalisers: E₀ = E of the corner-only mesh (the worst sensible error; 1 if the surface is
/// flat so that E₀ > 0) and T₀ = 2(W − 1)(H − 1), the triangle count of the full grid. Both
/// terms then run over about [0, 1] whatever the surface's scale and size.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scalarisation {
    /// Weight of the error, in [0, 1].
    pub w: f64,
    /// E₀.
    pub e0: f64,
    /// T₀.
    pub t0: f64,
}

impl Scalarisation {
    /// F of `o`.
    pub fn value(&self, o: &Objectives) -> f64 {
        self.w * o.e_sum / self.e0 + (1.0 - self.w) * o.t as f64 / self.t0
    }
}

/// Scores chromosomes on one height field and counts every evaluation.
pub struct Scorer {
    evaluator: Evaluator,
    indices: Vec<u32>,
    evaluations: u64,
    /// E₀ and T₀ of [`Scalarisation`].
    normalisers: (f64, f64),
}

impl Scorer {
    /// A scorer for `hf` (the corner-only mesh is scored once for E₀; that is not counted).
    pub fn new(hf: Arc<Heightfield>) -> Self {
        let mut evaluator = Evaluator::new(hf.clone());
        let e0 = evaluator
            .score(&hf.corners())
            .expect("corner indices are grid indices")
            .e_sum;
        let t0 = hf.full_triangles().max(1) as f64;
        Self {
            evaluator,
            indices: Vec::new(),
            evaluations: 0,
            normalisers: (if e0 > 0.0 { e0 } else { 1.0 }, t0),
        }
    }

    /// Evaluates `c` (one evaluation).
    pub fn score(&mut self, c: &Chromosome) -> Objectives {
        c.write_indices(&mut self.indices);
        self.evaluations += 1;
        // A chromosome has one bit per grid point, so its indices are always in range.
        let s = self
            .evaluator
            .score(&self.indices)
            .expect("chromosome indices are grid indices");
        Objectives {
            e_sum: s.e_sum,
            e_max: s.e_max,
            t: s.t,
        }
    }

    /// Evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The normalised weighted sum with weight `w` for this height field.
    pub fn scalarisation(&self, w: f64) -> Scalarisation {
        Scalarisation {
            w,
            e0: self.normalisers.0,
            t0: self.normalisers.1,
        }
    }

    /// The height field.
    pub fn heightfield(&self) -> &Arc<Heightfield> {
        self.evaluator.heightfield()
    }
}

/// Offers an evaluated chromosome to `front`, building the [`Solution`] (and its index list)
/// only when it would enter. Returns true when it entered.
pub fn offer(front: &mut Front, c: &Chromosome, o: &Objectives) -> bool {
    // The front is sorted by increasing T and decreasing E: the member with the largest
    // T ≤ o.t is the only one that can dominate or equal `o`.
    let members = front.solutions();
    let at = members.partition_point(|m| m.t <= o.t);
    if at > 0 && members[at - 1].e_sum <= o.e_sum {
        return false;
    }
    front.offer(Solution {
        e_sum: o.e_sum,
        e_max: o.e_max,
        t: o.t,
        kept: c.indices(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn normalisers_are_the_corner_mesh_error_and_the_full_grid_triangles() {
        // 3×3 grid, flat but for a bump of 4 in the middle: E₀ = 4 (corners only), T₀ = 8.
        let mut z = vec![0.0; 9];
        z[4] = 4.0;
        let hf = Arc::new(Heightfield::new(3, 3, z).unwrap());
        let mut scorer = Scorer::new(hf);
        let f = scorer.scalarisation(0.25);
        assert_eq!((f.e0, f.t0), (4.0, 8.0));
        let corners = Chromosome::from_indices(9, &[0, 2, 6, 8]);
        let o = scorer.score(&corners);
        assert_eq!((o.e_sum, o.t), (4.0, 2));
        assert_eq!(f.value(&o), 0.25 * 1.0 + 0.75 * 2.0 / 8.0);
        assert_eq!(scorer.evaluations(), 1, "E₀ itself is not counted");
    }

    #[test]
    fn offer_agrees_with_the_front() {
        // Random (E, T) pairs on a coarse lattice, so that ties in E, in T and in both occur:
        // the shortcut must accept exactly what `Front::offer` accepts.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(8);
        let (mut fast, mut plain) = (Front::default(), Front::default());
        let c = Chromosome::from_indices(4, &[0, 1, 2, 3]);
        for _ in 0..2000 {
            let o = Objectives {
                e_sum: rng.random_range(0..40) as f64,
                e_max: 0.0,
                t: rng.random_range(2..40),
            };
            let entered = offer(&mut fast, &c, &o);
            let expected = plain.offer(Solution {
                e_sum: o.e_sum,
                e_max: o.e_max,
                t: o.t,
                kept: c.indices(),
            });
            assert_eq!(entered, expected, "{o:?}");
        }
        assert_eq!(fast, plain);
    }
}
