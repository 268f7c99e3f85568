//! The normalised weighted sum of E and T, the scalar fitness of the weighted-sum GA and of
//! OAX's choice of the best-levels child.

use crate::evaluator::Score;
use serde::{Deserialize, Serialize};

/// F = w·E/E₀ + (1 − w)·T/T₀, to minimise.
///
/// Normalisers: E₀ = E of the corner-only mesh (the worst sensible error; 1 if the surface is
/// flat so that E₀ > 0) and T₀ = 2(W − 1)(H − 1), the triangle count of the full grid. Both
/// terms then run over about [0, 1] whatever the surface's scale and size.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Scalarisation {
    /// Weight of the error, in [0, 1].
    pub w: f64,
    /// E₀.
    pub e0: f64,
    /// T₀.
    pub t0: f64,
}

impl Scalarisation {
    /// F of `s`.
    pub(crate) fn value(&self, s: &Score) -> f64 {
        self.w * s.e_sum / self.e0 + (1.0 - self.w) * s.t as f64 / self.t0
    }
}
