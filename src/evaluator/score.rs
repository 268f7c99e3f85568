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

/// A score and the triangles it was measured on (grid-index triples, counter-clockwise).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// The numbers.
    #[serde(flatten)]
    pub score: Score,
    /// The triangles as grid indices (y·W + x).
    pub triangles: Vec<[u32; 3]>,
}
