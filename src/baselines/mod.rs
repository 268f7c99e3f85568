//! The classical baselines: greedy insertion (Garland & Heckbert 1995) and edge decimation
//! (after Schroeder et al. 1992).
//!
//! Both keep an exact, incrementally updated canonical Delaunay mesh (the same triangulation the
//! [`Evaluator`](crate::evaluator::Evaluator) builds for the same kept set) and record the numbers
//! of every solution they report from a fresh `Evaluator::score` of its kept set. Both are
//! deterministic: ties in their priority queues are broken by grid index.

pub(crate) mod bounded_decimation;
pub(crate) mod edge_decimation;
pub(crate) mod greedy_insertion;
pub(crate) mod max_error_mesh;
pub(crate) mod slot_heap;

// On real terrain: canonical meshes, honest records, stop contracts.
#[cfg(test)]
mod tests;

pub use edge_decimation::{DecimationParams, EdgeDecimation};
pub use greedy_insertion::{
    GreedyInsertion, GreedyParams, GreedyStop, InsertionRule, exactness_floor,
};
pub use max_error_mesh::{MaxErrorMesh, mesh_within};

use std::fmt;

/// Why a baseline's parameters were refused.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamsError {
    /// A parameter is out of its range; the message names it and the range.
    OutOfRange {
        /// The parameter's name.
        name: &'static str,
        /// What was given.
        value: f64,
        /// The allowed range, for people.
        allowed: &'static str,
    },
}

impl fmt::Display for ParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OutOfRange {
                name,
                value,
                allowed,
            } => write!(f, "{name} = {value} is not allowed: it must be {allowed}"),
        }
    }
}

impl std::error::Error for ParamsError {}
