//! The probability that a solution of one set dominates a solution of another: a primitive for
//! the paper's averaged dominance probability (Table V).

use super::{MetricsError, Point, check_non_empty};
use crate::front::dominates;

/// The probability that a point drawn uniformly from `a_set` Pareto-[dominates](crate::front::dominates)
/// a point drawn uniformly (and independently) from `b_set`: the number of pairs (a, b) with
/// a ≺ b divided by |A|·|B|.
///
/// Equivalently the mean, over the points a of A, of the fraction of B that a dominates. Strict
/// dominance: equal points do not count, so P(A, A) = 0 for a mutually non-dominated A, and
/// P(A, B) + P(B, A) ≤ 1 always (a ≺ b and b ≺ a cannot both hold). Averaging it over runs (or
/// pairs of runs) for a table, and testing the difference with
/// [`rank_sum_test`](super::rank_sum_test), is left to the caller.
///
/// Errors: [`MetricsError::Empty`] if either set is empty; [`MetricsError::NonFinite`] for NaN
/// or infinite coordinates.
///
/// ```
/// use paretomesh::metrics::dominance_probability;
/// let a = [[1.0, 1.0], [5.0, 5.0]];
/// let b = [[2.0, 2.0], [0.0, 9.0]];
/// // Of the 4 pairs only (1, 1) ≺ (2, 2) holds.
/// assert_eq!(dominance_probability(&a, &b).unwrap(), 0.25);
/// ```
pub fn dominance_probability(a_set: &[Point], b_set: &[Point]) -> Result<f64, MetricsError> {
    check_non_empty(a_set, "A")?;
    check_non_empty(b_set, "B")?;
    let pairs = a_set
        .iter()
        .map(|&a| b_set.iter().filter(|&&b| dominates(a, b)).count())
        .sum::<usize>();
    Ok(pairs as f64 / (a_set.len() as f64 * b_set.len() as f64))
}
