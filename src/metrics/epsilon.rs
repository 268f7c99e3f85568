//! The binary epsilon indicators of Zitzler, Thiele, Laumanns, Fonseca & Grunert da Fonseca,
//! "Performance assessment of multiobjective optimizers: an analysis and review", IEEE TEVC 7(2),
//! 2003: the smallest ε such that every point of B is weakly ε-dominated by some point of A.

use super::{MetricsError, Point, check_non_empty};

/// The additive epsilon indicator I_ε+(A, B): the smallest ε such that every `b` in `b_set` has
/// an `a` in `a_set` with `a_i − ε ≤ b_i` in both objectives.
///
/// I_ε+(A, B) = max over b of min over a of max over i of (a_i − b_i). It is ≤ 0 exactly when A
/// weakly dominates every point of B, and I_ε+(A, A) = 0. Not symmetric: report both orders.
/// The value is in objective units, so normalise first when objectives differ in scale.
///
/// Errors: [`MetricsError::Empty`] if either set is empty; [`MetricsError::NonFinite`] for NaN
/// or infinite coordinates.
///
/// ```
/// use paretomesh::metrics::additive_epsilon;
/// // (1, 3) must shift by 1 in E to weakly dominate (0, 4): max(1 − 0, 3 − 4) = 1.
/// assert_eq!(additive_epsilon(&[[1.0, 3.0]], &[[0.0, 4.0]]).unwrap(), 1.0);
/// ```
pub fn additive_epsilon(a_set: &[Point], b_set: &[Point]) -> Result<f64, MetricsError> {
    check_non_empty(a_set, "A")?;
    check_non_empty(b_set, "B")?;
    Ok(max_min_max(a_set, b_set, |a, b| a - b))
}

/// The multiplicative epsilon indicator I_ε(A, B): the smallest ε such that every `b` in `b_set`
/// has an `a` in `a_set` with `a_i ≤ ε·b_i` in both objectives.
///
/// I_ε(A, B) = max over b of min over a of max over i of (a_i / b_i). It is ≤ 1 exactly when A
/// weakly dominates every point of B, and I_ε(A, A) = 1 for positive points. Not symmetric.
/// Scale-free: multiplying an objective by a positive constant in both sets changes nothing.
///
/// Contract on signs. Zitzler et al. define it for strictly positive objectives, which
/// normalised (E, T) are except for an exact mesh (E = 0, e.g. the full grid). Zero is
/// accepted with the limit of the definition `a_i ≤ ε·b_i`: when `b_i = 0` the condition holds
/// for every ε if `a_i = 0` (that objective sets no bound) and for no ε if `a_i > 0` (the ratio
/// is +∞). So the result can be `f64::INFINITY`: a B containing an exact mesh (E = 0) that A
/// does not match. Negative coordinates have no meaning here and are an error.
///
/// Errors: [`MetricsError::Empty`] if either set is empty; [`MetricsError::NonFinite`] for NaN
/// or infinite coordinates; [`MetricsError::Negative`] for a negative coordinate.
///
/// ```
/// use paretomesh::metrics::multiplicative_epsilon;
/// // (2, 3) covers (1, 6) once (1, 6) is scaled by 2 (2 ≤ 2·1, 3 ≤ 2·6).
/// assert_eq!(multiplicative_epsilon(&[[2.0, 3.0]], &[[1.0, 6.0]]).unwrap(), 2.0);
/// ```
pub fn multiplicative_epsilon(a_set: &[Point], b_set: &[Point]) -> Result<f64, MetricsError> {
    check_non_empty(a_set, "A")?;
    check_non_empty(b_set, "B")?;
    check_non_negative(a_set, "A")?;
    check_non_negative(b_set, "B")?;
    Ok(max_min_max(a_set, b_set, ratio_bound))
}

/// The smallest ε ≥ 0 with `a ≤ ε·b`, for `a, b ≥ 0`: 0 when both are 0 (no bound), +∞ when
/// only `b` is 0.
fn ratio_bound(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        a / b
    } else if a > 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}

/// max over b of min over a of max over i of `pair(a_i, b_i)`: both sets non-empty.
fn max_min_max(a_set: &[Point], b_set: &[Point], pair: impl Fn(f64, f64) -> f64) -> f64 {
    b_set
        .iter()
        .map(|b| {
            a_set
                .iter()
                .map(|a| pair(a[0], b[0]).max(pair(a[1], b[1])))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

fn check_non_negative(points: &[Point], set: &'static str) -> Result<(), MetricsError> {
    match points.iter().position(|p| p[0] < 0.0 || p[1] < 0.0) {
        Some(index) => Err(MetricsError::Negative { set, index }),
        None => Ok(()),
    }
}
