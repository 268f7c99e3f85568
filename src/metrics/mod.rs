//! Indicators and statistics for comparing fronts: hypervolume, epsilon, coverage, Wilcoxon
//! rank-sum, and the paper's trade-off pick.
//!
//! Everything works on plain slices of objective points [`Point`] = `[E, T]`, both minimised,
//! so the same functions serve one run's front, the merge of many runs, or a reference front.
//! [`objectives`] turns [`Solution`]s into points. Functions that compare *values* (hypervolume,
//! epsilon) should be given points normalised per dataset with a [`Normalization`]; dominance
//! based ones (coverage, filtering, dominance probability) do not care, since dividing each
//! objective by a positive constant keeps every dominance relation.
//!
//! Every function checks its inputs: a NaN or infinite coordinate, or an empty set where the
//! indicator is undefined, is a [`MetricsError`], never a panic.
//!
//! Coverage: [`coverage`] is Zitzler's C(A, B) with weak dominance, as published (C(A, A) = 1);
//! [`strict_coverage`] is the strict-dominance variant (C(A, A) = 0 for a non-dominated A). They
//! differ only on solutions both sets found.
//!
//! The paper's comparison of two methods on one dataset, in outline:
//!
//! ```
//! use paretomesh::metrics::{self, DEFAULT_REFERENCE_POINT, Normalization};
//! // Raw (E, T) fronts of two methods; E of the corner-only mesh 120, full grid 2048 triangles.
//! let a_raw = [[120.0, 2.0], [40.0, 60.0], [10.0, 400.0]];
//! let b_raw = [[120.0, 2.0], [50.0, 60.0], [5.0, 900.0]];
//! let n = Normalization::new(120.0, 2048.0).unwrap();
//! let (a, b) = (n.apply_all(&a_raw), n.apply_all(&b_raw));
//! let reference_front = metrics::merge([&a[..], &b[..]]).unwrap();
//! let hvr_a = metrics::hypervolume_ratio(&a, &reference_front, DEFAULT_REFERENCE_POINT).unwrap();
//! let hvr_b = metrics::hypervolume_ratio(&b, &reference_front, DEFAULT_REFERENCE_POINT).unwrap();
//! assert!(hvr_a < 1.0 && hvr_b < 1.0); // each misses a part of the merge
//! let eps = metrics::additive_epsilon(&a, &b).unwrap();
//! let c_ab = metrics::coverage(&a, &b).unwrap(); // (120, 2) shared, (50, 60) dominated: 2/3
//! assert!((c_ab - 2.0 / 3.0).abs() < 1e-12 && eps > 0.0);
//! let pick = metrics::trade_off_pick(&a, 1).unwrap();
//! assert!(pick.index < a.len());
//! ```

mod coverage;
mod dominance;
mod epsilon;
mod hypervolume;
mod nondominated;
mod normalization;
mod tradeoff;
mod wilcoxon;

// Against hand-computed values, textbook tables, brute force and published examples.
#[cfg(test)]
mod tests;

pub use coverage::{coverage, strict_coverage};
pub use dominance::dominance_probability;
pub use epsilon::{additive_epsilon, multiplicative_epsilon};
pub use hypervolume::{hypervolume, hypervolume_ratio};
pub use nondominated::{merge, non_dominated};
pub use normalization::{DEFAULT_REFERENCE_POINT, Normalization};
pub use tradeoff::{
    TradeOffPick, best_error_pick, fewest_triangles_pick, trade_off_pick, trade_off_pick_with,
};
pub use wilcoxon::{RankSumMethod, RankSumTest, exact_u_cdf, rank_sum_test, rank_sum_test_with};

use crate::evaluator::EvaluateError;
use crate::front::Solution;
use std::fmt;

/// An objective vector `[E, T]` (error, triangle count), both minimised.
pub type Point = [f64; 2];

/// The objective points of some solutions, in the same order.
pub fn objectives(solutions: &[Solution]) -> Vec<Point> {
    solutions.iter().map(Solution::objectives).collect()
}

/// Why an indicator or a test could not be computed.
#[derive(Clone, Debug, PartialEq)]
pub enum MetricsError {
    /// A coordinate is NaN or infinite.
    NonFinite {
        /// Which input ("A", "B", "front", "reference point", "sample 1"...).
        set: &'static str,
        /// Position of the offending point or value in that input.
        index: usize,
    },
    /// A coordinate is negative where the indicator needs non-negative values.
    Negative {
        /// Which input.
        set: &'static str,
        /// Position of the offending point in that input.
        index: usize,
    },
    /// An input is empty where the indicator is undefined for an empty set.
    Empty {
        /// Which input.
        set: &'static str,
    },
    /// A normalisation scale is not a positive finite number.
    BadScale {
        /// Which scale ("E" or "T").
        objective: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// The reference front has a hypervolume of zero, so a ratio to it is undefined.
    ZeroReferenceHypervolume,
    /// The exact rank-sum distribution was requested for tied samples (it assumes no ties).
    ExactWithTies,
    /// The exact rank-sum distribution was requested for samples too large to tabulate.
    ExactTooLarge {
        /// Size of the first sample.
        n1: usize,
        /// Size of the second sample.
        n2: usize,
    },
    /// The evaluator could not score a mesh needed for normalisation.
    Evaluate(EvaluateError),
}

impl fmt::Display for MetricsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite { set, index } => {
                write!(f, "{set}: value {index} is NaN or infinite")
            }
            Self::Negative { set, index } => write!(
                f,
                "{set}: point {index} has a negative objective; this indicator needs E ≥ 0 and T ≥ 0"
            ),
            Self::Empty { set } => {
                write!(
                    f,
                    "{set} is empty: the indicator is undefined for an empty set"
                )
            }
            Self::BadScale { objective, value } => write!(
                f,
                "the {objective} normalisation scale is {value}; it must be a positive finite number"
            ),
            Self::ZeroReferenceHypervolume => write!(
                f,
                "the reference front has zero hypervolume (no point strictly better than the reference point), so the hypervolume ratio is undefined"
            ),
            Self::ExactWithTies => write!(
                f,
                "the exact rank-sum distribution assumes no ties, but the samples have tied values; use the normal approximation"
            ),
            Self::ExactTooLarge { n1, n2 } => write!(
                f,
                "samples of sizes {n1} and {n2} are too large for the exact rank-sum distribution (n1·n2 must be at most {}); use the normal approximation",
                wilcoxon::EXACT_TABLE_LIMIT
            ),
            Self::Evaluate(e) => write!(f, "could not score the corner-only mesh: {e}"),
        }
    }
}

impl std::error::Error for MetricsError {}

/// Checks that every coordinate of `points` is finite.
fn check_finite(points: &[Point], set: &'static str) -> Result<(), MetricsError> {
    match points
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        Some(index) => Err(MetricsError::NonFinite { set, index }),
        None => Ok(()),
    }
}

/// Checks that `points` is non-empty and every coordinate is finite.
fn check_non_empty(points: &[Point], set: &'static str) -> Result<(), MetricsError> {
    if points.is_empty() {
        return Err(MetricsError::Empty { set });
    }
    check_finite(points, set)
}

/// Weak Pareto dominance (`a ≼ b`): `a` is no worse than `b` in both objectives. Minimisation.
/// Every point weakly dominates itself.
fn weakly_dominates(a: Point, b: Point) -> bool {
    a[0] <= b[0] && a[1] <= b[1]
}
