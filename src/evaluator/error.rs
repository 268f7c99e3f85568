//! Why a kept set, a triangulation or an edit could not be scored.

use std::fmt;

/// Why a kept set or a triangulation could not be scored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EvaluateError {
    /// A grid index is not below N.
    IndexOutOfRange { index: u64, len: usize },
    /// A triangle has two equal or three collinear vertices.
    DegenerateTriangle { triangle: [u32; 3] },
    /// An edge is used twice in the same direction: triangles overlap or are duplicated.
    OverlappingEdge { from: u32, to: u32 },
    /// An edge is used by one triangle only but does not lie on the grid border: a hole or a
    /// T-junction.
    OpenEdge { from: u32, to: u32 },
    /// The triangles do not cover the grid rectangle exactly once.
    WrongArea { found: i64, expected: i64 },
    /// An edit of a [`MeshState`](crate::evaluator::MeshState) removes a point that is not kept (or a corner), or inserts a
    /// point that is kept already.
    InvalidEdit { index: u32, why: &'static str },
    /// A [`MeshState`](crate::evaluator::MeshState) was edited that this evaluator's height field did not score (or that
    /// holds a triangulation given from outside).
    ForeignState,
}

impl fmt::Display for EvaluateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::IndexOutOfRange { index, len } => {
                write!(
                    f,
                    "grid index {index} is out of range: the grid has {len} points"
                )
            }
            Self::DegenerateTriangle { triangle } => {
                write!(
                    f,
                    "triangle {triangle:?} is degenerate (repeated or collinear vertices)"
                )
            }
            Self::OverlappingEdge { from, to } => write!(
                f,
                "edge {from}→{to} is used twice in the same direction: triangles overlap"
            ),
            Self::OpenEdge { from, to } => write!(
                f,
                "edge {from}–{to} belongs to one triangle only but is not on the grid border (a hole or a T-junction)"
            ),
            Self::WrongArea { found, expected } => write!(
                f,
                "the triangles cover an area of {} cells, the grid has {} (they must cover it exactly once)",
                *found as f64 / 2.0,
                *expected as f64 / 2.0
            ),
            Self::InvalidEdit { index, why } => {
                write!(f, "cannot edit grid point {index}: {why}")
            }
            Self::ForeignState => write!(
                f,
                "the mesh state was not scored from a kept set on this evaluator's height field"
            ),
        }
    }
}

impl std::error::Error for EvaluateError {}

/// `Err(`[`EvaluateError::IndexOutOfRange`]`)` for the first of `indices` that is not below
/// `len` (the number of grid points), else `Ok`.
pub fn check_indices(indices: &[u32], len: usize) -> Result<(), EvaluateError> {
    match indices.iter().find(|&&i| i as usize >= len) {
        Some(&bad) => Err(EvaluateError::IndexOutOfRange {
            index: bad.into(),
            len,
        }),
        None => Ok(()),
    }
}
