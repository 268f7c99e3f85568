//! Zitzler's coverage indicator C(A, B) (the "set coverage" of Zitzler & Thiele, "Multiobjective
//! evolutionary algorithms: a comparative case study and the strength Pareto approach", IEEE
//! TEVC 3(4), 1999), and a strict-dominance variant.

use super::{MetricsError, Point, check_finite, check_non_empty, weakly_dominates};
use crate::front::dominates;

/// Zitzler's coverage C(A, B): the fraction of the points of `b_set` that are *weakly* dominated
/// by (no worse in both objectives than) at least one point of `a_set`.
///
/// This is the published definition: Zitzler & Thiele (1999) count `b` as covered when some `a`
/// dominates *or equals* it (a ≼ b). Consequences: C(A, A) = 1 for any non-empty A; C(A, B) = 1
/// when every point of B is dominated by or equal to a point of A; C(A, B) = 0 when no point of
/// B is. Not symmetric: report both C(A, B) and C(B, A). Two methods that find the same solution
/// (such as the corner-only mesh) both cover it; see [`strict_coverage`] for the variant that
/// does not count equal points.
///
/// Duplicates in `b_set` are counted as often as they appear, so pass de-duplicated fronts
/// ([`non_dominated`](super::non_dominated)). An empty `a_set` covers nothing (0).
///
/// Errors: [`MetricsError::Empty`] if `b_set` is empty (the fraction is 0/0);
/// [`MetricsError::NonFinite`] for NaN or infinite coordinates.
///
/// ```
/// use paretomesh::metrics::coverage;
/// let a = [[1.0, 4.0], [3.0, 2.0]];
/// let b = [[1.0, 4.0], [4.0, 3.0], [0.0, 9.0]];
/// // (1, 4) is equal to a point of A, (4, 3) is dominated by (3, 2), (0, 9) by none: 2 of 3.
/// assert_eq!(coverage(&a, &b).unwrap(), 2.0 / 3.0);
/// ```
pub fn coverage(a_set: &[Point], b_set: &[Point]) -> Result<f64, MetricsError> {
    covered_fraction(a_set, b_set, weakly_dominates)
}

/// The strict-dominance variant of coverage: the fraction of the points of `b_set` that are
/// Pareto-[dominated](crate::front::dominates) (no worse in both objectives, strictly better in
/// one) by at least one point of `a_set`.
///
/// It differs from [`coverage`] only on points of B that are equal to a point of A (and
/// dominated by none): they count as covered there and not here. So for a mutually
/// non-dominated A, strict C(A, A) = 0, a value worth checking, while C(A, B) = 1
/// when every point of B is strictly dominated by some point of A, under both definitions.
///
/// Same contract as [`coverage`]: `b_set` must be non-empty, coordinates finite.
///
/// ```
/// use paretomesh::metrics::strict_coverage;
/// let a = [[1.0, 4.0], [3.0, 2.0]];
/// let b = [[1.0, 4.0], [4.0, 3.0], [0.0, 9.0]];
/// // Only (4, 3) is strictly dominated (by (3, 2)); (1, 4) is merely equal: 1 of 3.
/// assert_eq!(strict_coverage(&a, &b).unwrap(), 1.0 / 3.0);
/// ```
pub fn strict_coverage(a_set: &[Point], b_set: &[Point]) -> Result<f64, MetricsError> {
    covered_fraction(a_set, b_set, dominates)
}

fn covered_fraction(
    a_set: &[Point],
    b_set: &[Point],
    covers: fn(Point, Point) -> bool,
) -> Result<f64, MetricsError> {
    check_finite(a_set, "A")?;
    check_non_empty(b_set, "B")?;
    let covered = b_set
        .iter()
        .filter(|&&b| a_set.iter().any(|&a| covers(a, b)))
        .count();
    Ok(covered as f64 / b_set.len() as f64)
}
