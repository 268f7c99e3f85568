//! Exact arithmetic, the evaluator's bottom layer: integer predicates with the tie rule that
//! makes the triangulation canonical, fixed-point error sums that are the same in any order,
//! and the paper's E by brute force, the reference the fast paths are tested against.

pub(crate) mod fixed_point;
#[cfg(test)]
pub(crate) mod paper_e;
pub(crate) mod predicates;
