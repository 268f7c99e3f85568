//! The numbers the evaluator gives a mesh: the vocabulary every layer of it speaks.

use serde::{Deserialize, Serialize};

/// The error numbers of one mesh.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Score {
    /// E = Σ |z − z̃| over all grid points.
    #[serde(rename = "E_sum")]
    pub e_sum: f64,
    /// max |z − z̃|.
    #[serde(rename = "E_max")]
    pub e_max: f64,
    /// sqrt(Σ (z − z̃)² / N).
    pub rms: f64,
    /// Number of triangles.
    #[serde(rename = "T")]
    pub t: usize,
}

impl Score {
    /// The score of a mesh of `t` triangles on a grid of `n` points whose errors total
    /// (Σ error, Σ error², max error), as [`ErrorUnits::values`](crate::evaluator::exact::fixed_point::ErrorUnits::values)
    /// gives them: how every path turns exact totals into a score.
    pub(crate) fn from_values((sum, sum_sq, max): (f64, f64, f64), n: usize, t: usize) -> Self {
        Self {
            e_sum: sum,
            e_max: max,
            rms: (sum_sq / n as f64).sqrt(),
            t,
        }
    }
}

/// A score and the triangles it was measured on (grid-index triples, counter-clockwise).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// The numbers.
    #[serde(flatten)]
    pub score: Score,
    /// The triangles as grid indices (y·W + x).
    pub triangles: Vec<[u32; 3]>,
}
