//! Non-dominated filtering and merging of objective points.

use super::{MetricsError, Point, check_finite};
use crate::front::dominates;
use std::cmp::Ordering;

/// The non-dominated subset of `points`: every point that no other point
/// [dominates](crate::front::dominates), with objective-equal points kept once.
///
/// The result is sorted by increasing T then increasing E; since its points are mutually
/// non-dominated, that is increasing T and strictly decreasing E. The order of the input does not
/// matter: any permutation gives the same output. An empty input gives an empty output.
///
/// `-0.0` and `0.0` count as equal (they compare equal); the one kept is the first in sorted
/// order. Errors: [`MetricsError::NonFinite`] if a coordinate is NaN or infinite.
///
/// ```
/// use paretomesh::metrics::non_dominated;
/// // (3, 4) is dominated by (2, 4); (1, 6) appears twice.
/// let front = non_dominated(&[[1.0, 6.0], [3.0, 4.0], [2.0, 4.0], [1.0, 6.0], [5.0, 2.0]]).unwrap();
/// assert_eq!(front, vec![[5.0, 2.0], [2.0, 4.0], [1.0, 6.0]]);
/// ```
pub fn non_dominated(points: &[Point]) -> Result<Vec<Point>, MetricsError> {
    check_finite(points, "points")?;
    let mut sorted = points.to_vec();
    sorted.sort_by(by_t_then_e);
    // Sweep by increasing T (then E): a point survives iff its E is strictly below every E seen
    // so far. An earlier point with E ≤ this E has T ≤ this T, so it dominates this point or
    // equals it (a duplicate); an earlier point with larger E cannot dominate it.
    let mut front: Vec<Point> = Vec::with_capacity(sorted.len());
    for p in sorted {
        match front.last() {
            Some(&last) if last[0] <= p[0] => {
                debug_assert!(dominates(last, p) || last == p);
            }
            _ => front.push(p),
        }
    }
    Ok(front)
}

/// The non-dominated merge of several point sets (fronts, runs, methods): the
/// [`non_dominated`] subset of their union, duplicates kept once, sorted by T then E.
///
/// Merging nothing, or only empty sets, gives an empty front. Errors:
/// [`MetricsError::NonFinite`] if a coordinate is NaN or infinite.
///
/// ```
/// use paretomesh::metrics::merge;
/// let a = [[4.0, 2.0], [1.0, 8.0]];
/// let b = [[2.0, 4.0], [4.0, 2.0]];
/// assert_eq!(merge([&a[..], &b[..]]).unwrap(), vec![[4.0, 2.0], [2.0, 4.0], [1.0, 8.0]]);
/// ```
pub fn merge<'a>(sets: impl IntoIterator<Item = &'a [Point]>) -> Result<Vec<Point>, MetricsError> {
    let union: Vec<Point> = sets.into_iter().flatten().copied().collect();
    non_dominated(&union)
}

/// Total order by T, then E (finite values only, so `partial_cmp` never fails; `total_cmp`
/// would separate `-0.0` from `0.0`, which must stay equal for duplicate removal).
fn by_t_then_e(a: &Point, b: &Point) -> Ordering {
    let t = a[1].partial_cmp(&b[1]).unwrap_or(Ordering::Equal);
    t.then(a[0].partial_cmp(&b[0]).unwrap_or(Ordering::Equal))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_does_not_depend_on_input_order() {
        // Three mutually non-dominated points plus one dominated and one duplicate, in two orders.
        let a = [[3.0, 1.0], [1.0, 3.0], [2.0, 2.0], [3.0, 3.0], [2.0, 2.0]];
        let mut b = a;
        b.reverse();
        let expected = vec![[3.0, 1.0], [2.0, 2.0], [1.0, 3.0]];
        assert_eq!(non_dominated(&a).unwrap(), expected);
        assert_eq!(non_dominated(&b).unwrap(), expected);
    }

    #[test]
    fn equal_t_keeps_only_the_lowest_e() {
        // Same T = 4: (2, 4) dominates (5, 4).
        assert_eq!(
            non_dominated(&[[5.0, 4.0], [2.0, 4.0]]).unwrap(),
            vec![[2.0, 4.0]]
        );
    }

    #[test]
    fn equal_e_keeps_only_the_lowest_t() {
        // Same E = 2: (2, 3) dominates (2, 9).
        assert_eq!(
            non_dominated(&[[2.0, 9.0], [2.0, 3.0]]).unwrap(),
            vec![[2.0, 3.0]]
        );
    }

    #[test]
    fn signed_zeros_are_one_point() {
        // E = -0.0 and E = 0.0 are the same objective value: one point survives.
        assert_eq!(non_dominated(&[[0.0, 2.0], [-0.0, 2.0]]).unwrap().len(), 1);
    }

    #[test]
    fn nan_is_an_error() {
        assert_eq!(
            non_dominated(&[[1.0, 2.0], [f64::NAN, 1.0]]),
            Err(MetricsError::NonFinite {
                set: "points",
                index: 1
            })
        );
    }
}
