//! Exact 2-D hypervolume (the area a set dominates up to a reference point) and the
//! hypervolume ratio HVR.

use super::{MetricsError, Point, check_finite, non_dominated};

/// The hypervolume of `points` for minimisation: the area of the region that some point
/// weakly dominates and that is bounded by `reference` (the union of the boxes
/// `[E, r_E] × [T, r_T]`).
///
/// Only points strictly better than `reference` in both objectives contribute; others (and
/// dominated points, and duplicates) add nothing. The empty set has hypervolume 0. Exact up to
/// floating-point rounding: one sweep over the sorted non-dominated subset, O(n log n).
///
/// Errors: [`MetricsError::NonFinite`] if a coordinate of `points` or `reference` is NaN or
/// infinite.
///
/// ```
/// use paretomesh::metrics::hypervolume;
/// // One point (4, 6) under reference (10, 10): a 6 × 4 box.
/// assert_eq!(hypervolume(&[[4.0, 6.0]], [10.0, 10.0]).unwrap(), 24.0);
/// ```
pub fn hypervolume(points: &[Point], reference: Point) -> Result<f64, MetricsError> {
    check_finite(points, "points")?;
    check_finite(&[reference], "reference point")?;
    let inside: Vec<Point> = points
        .iter()
        .copied()
        .filter(|p| p[0] < reference[0] && p[1] < reference[1])
        .collect();
    // Sorted by increasing T and strictly decreasing E: point i owns the slab from its T to the
    // next point's T (or r_T), of width r_E − E_i.
    let front = non_dominated(&inside)?;
    let mut area = 0.0;
    for (i, p) in front.iter().enumerate() {
        let next_t = front.get(i + 1).map_or(reference[1], |q| q[1]);
        area += (reference[0] - p[0]) * (next_t - p[1]);
    }
    Ok(area)
}

/// The hypervolume ratio HVR = HV(`front`) / HV(`reference_front`), both with the same
/// `reference` point.
///
/// The reference front is meant to be the non-dominated [merge](super::merge) of every method's
/// front (so HVR ≤ 1 for each of them, = 1 for a front that reaches all of it). Both should be
/// normalised with the same [`Normalization`](super::Normalization) first.
///
/// Errors: [`MetricsError::NonFinite`] for NaN or infinite coordinates;
/// [`MetricsError::ZeroReferenceHypervolume`] if the reference front has hypervolume 0 (empty,
/// or no point strictly better than `reference`), since the ratio is then undefined.
///
/// ```
/// use paretomesh::metrics::hypervolume_ratio;
/// // A 1 × 1 box against a 2 × 2 box: a quarter.
/// let hvr = hypervolume_ratio(&[[1.0, 1.0]], &[[0.0, 0.0]], [2.0, 2.0]).unwrap();
/// assert_eq!(hvr, 0.25);
/// ```
pub fn hypervolume_ratio(
    front: &[Point],
    reference_front: &[Point],
    reference: Point,
) -> Result<f64, MetricsError> {
    let hv = hypervolume(front, reference)?;
    let reference_hv = hypervolume(reference_front, reference)?;
    if reference_hv <= 0.0 {
        return Err(MetricsError::ZeroReferenceHypervolume);
    }
    Ok(hv / reference_hv)
}
