//! The errors of a mesh's grid points, summed exactly.
//!
//! Floating-point addition is not associative, so a float E_sum would depend on the order its
//! terms are added in: on how the triangulation was built or numbered. The evaluator therefore
//! sums in fixed point ([`ErrorUnits`]): each error is rounded to a whole number of units of
//! one power of two, chosen per height field so that no sum can overflow, and the integers are
//! added, which is exact in any order. A mesh scored from scratch, the same mesh reached by local
//! edits or composed from two parents ([`MeshState`](crate::evaluator::MeshState), which keeps each
//! triangle's totals), and a one-pass score all get the same bits; an edit re-rasterises only
//! the triangles it touched, and a composition reuses its parents' triangles' totals.

/// The fixed-point units E_sum and Σ error² are summed in, for one height field.
///
/// An error `d` counts as d·2ᵏ rounded to the nearest integer. `k` is the largest exponent that
/// keeps every term below 2⁵¹ and any sum of N terms below 2⁶² (each error is at most the z
/// range R, as z̃ interpolates heights within it): 2ᵏ·R ≤ min(2⁵¹, 2⁶²/2N). Rounding loses at
/// most half a unit per point, R·2⁻⁵² or (for grids over 2¹⁰ points) N·R·2⁻⁶⁰: under 10⁻¹⁴ of R
/// per point on a 257×257 grid, far inside the 1e-9 relative accuracy E_sum is held to. A power
/// of two makes d·2ᵏ exact, and terms below 2⁵¹ round by one floating-point addition (see
/// [`units`](Self::units)): the same integers natively and in wasm, without a branch.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ErrorUnits {
    /// 2ᵏ for |z − z̃|.
    pub(crate) scale: f64,
    /// The same for (z − z̃)², with R² in place of R.
    pub(crate) scale_sq: f64,
    /// 2^top, the largest term: a bound only heights beyond 10¹⁵⁰ (whose squares overflow)
    /// could reach, so that no sum can overflow whatever the input.
    pub(crate) cap: f64,
}

/// 2⁵²: added to a number in [0, 2⁵¹], it leaves that number rounded to an integer in the low
/// bits of the sum's mantissa.
pub(crate) const ROUNDER: f64 = 4_503_599_627_370_496.0;

impl ErrorUnits {
    /// The units for `points` grid points with heights spanning `z_range` (max − min, ≥ 0).
    pub(crate) fn new(points: usize, z_range: f64) -> Self {
        // 2^b ≥ 2N.
        let b = (2 * points.max(1)).next_power_of_two().trailing_zeros() as i32;
        let top = 51.min(62 - b);
        // 2^e ≥ R, read off R's bits (a library log2 may differ between platforms in its last
        // bit, and so in its ceiling). A flat field's errors are rounding noise: any unit will
        // do, and so will one for an absurdly small range.
        let e = if z_range.is_finite() && z_range >= 1e-300 {
            let bits = z_range.to_bits();
            let exponent = ((bits >> 52) & 0x7ff) as i32 - 1023;
            let mantissa = bits & ((1 << 52) - 1);
            exponent + i32::from(mantissa != 0)
        } else {
            0
        };
        // Exactly 2^k, in the normal range.
        let exp2 = |k: i32| f64::from_bits(((k.clamp(-1000, 1000) + 1023) as u64) << 52);
        Self {
            scale: exp2(top - e),
            scale_sq: exp2(top - 2 * e),
            cap: exp2(top),
        }
    }

    /// The units of height field `hf`.
    pub(crate) fn of(hf: &crate::heightfield::Heightfield) -> Self {
        let (lo, hi) = hf.z_range();
        Self::new(hf.len(), hi - lo)
    }

    /// d·2ᵏ rounded to the nearest integer (ties to even), for an error `d` ≥ 0.
    #[inline]
    pub(crate) fn units(&self, d: f64) -> u64 {
        to_integer(at_most(d * self.scale, self.cap))
    }

    /// The units of d².
    #[inline]
    pub(crate) fn units_sq(&self, d: f64) -> u64 {
        to_integer(at_most(d * d * self.scale_sq, self.cap))
    }

    /// A sum of [`units`](Self::units) as a number.
    pub(crate) fn value(&self, units: u64) -> f64 {
        units as f64 / self.scale
    }

    /// A sum of [`units_sq`](Self::units_sq) as a number.
    pub(crate) fn value_sq(&self, units: u64) -> f64 {
        units as f64 / self.scale_sq
    }

    /// (Σ error, Σ error², max error) of `totals` as numbers.
    pub(crate) fn values(&self, totals: &ErrorTotals) -> (f64, f64, f64) {
        (
            self.value(totals.sum),
            self.value_sq(totals.sum_sq),
            totals.max,
        )
    }
}

/// min(x, cap) for a non-NaN `x` in one comparison (`f64::min`'s NaN rule costs several
/// instructions per point).
#[inline]
fn at_most(x: f64, cap: f64) -> f64 {
    if x < cap { x } else { cap }
}

/// `x` ∈ [0, 2⁵¹] rounded to the nearest integer: x + 2⁵² has a unit last place, so the sum
/// rounds x, and its mantissa then holds it. Why not `as`: Rust's saturating float-to-integer
/// conversion costs compares and branches per point, a large share of a sparse mesh's raster.
#[inline]
fn to_integer(x: f64) -> u64 {
    (x + ROUNDER).to_bits() - ROUNDER.to_bits()
}

/// Error totals over some grid points, in [`ErrorUnits`] (exact, so they add in any order).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ErrorTotals {
    /// Σ units(|z − z̃|).
    pub sum: u64,
    /// Σ units((z − z̃)²).
    pub sum_sq: u64,
    /// max |z − z̃| (0 when empty).
    pub max: f64,
}

impl ErrorTotals {
    /// Adds one point's error `d` (≥ 0, not NaN), in `units`.
    #[inline]
    pub(crate) fn add_error(&mut self, units: ErrorUnits, d: f64) {
        self.sum += units.units(d);
        self.sum_sq += units.units_sq(d);
        self.max = if d > self.max { d } else { self.max };
    }

    /// Adds `other`'s points to these.
    #[inline]
    pub(crate) fn add(&mut self, other: &Self) {
        self.sum += other.sum;
        self.sum_sq += other.sum_sq;
        // Errors are never NaN (heights are finite), so a comparison is the maximum.
        self.max = if other.max > self.max {
            other.max
        } else {
            self.max
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// The totals of `errors` in `units`, point by point.
    fn totals_of(units: ErrorUnits, errors: &[f64]) -> ErrorTotals {
        let mut t = ErrorTotals::default();
        for &d in errors {
            t.add_error(units, d);
        }
        t
    }

    /// Errors like a mesh's: mostly small, a few near the range, some exactly zero.
    fn errors(n: usize, range: f64, seed: u64) -> Vec<f64> {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
        (0..n)
            .map(|k| match k % 7 {
                0 => 0.0,
                1 => range * rng.random::<f64>(),
                _ => range * rng.random::<f64>().powi(4),
            })
            .collect()
    }

    fn total(units: ErrorUnits, d: &[f64]) -> (f64, f64, f64) {
        units.values(&totals_of(units, d))
    }

    #[test]
    fn totals_do_not_depend_on_the_order_of_the_errors() {
        // Why fixed point: a float sum of the same terms in another order differs in its last
        // bits, which would make a mesh's score depend on how it was built.
        let d = errors(4225, 83.5, 1);
        let units = ErrorUnits::new(d.len(), 83.5);
        let forward = total(units, &d);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(2);
        let mut shuffled = d.clone();
        for i in (1..shuffled.len()).rev() {
            shuffled.swap(i, rng.random_range(0..=i));
        }
        let reversed: Vec<f64> = d.iter().rev().copied().collect();
        for other in [shuffled, reversed] {
            let t = total(units, &other);
            assert_eq!(forward.0.to_bits(), t.0.to_bits());
            assert_eq!(forward.1.to_bits(), t.1.to_bits());
            assert_eq!(forward.2.to_bits(), t.2.to_bits());
        }
        // Split in two (as a mesh's triangles split its points), the parts add to the whole.
        let (a, b) = d.split_at(1234);
        let mut parts = totals_of(units, a);
        parts.add(&totals_of(units, b));
        assert_eq!(parts, totals_of(units, &d));
    }

    #[test]
    fn totals_are_accurate_for_large_and_small_ranges() {
        for (n, range) in [
            (4, 1.0),
            (1089, 1e-6),
            (4225, 83.5),
            (66_049, 4096.0),
            (1_050_625, 3.7e5),
        ] {
            let d = errors(n, range, n as u64);
            let units = ErrorUnits::new(n, range);
            let (sum, sum_sq, max) = total(units, &d);
            let exact_sum: f64 = d.iter().sum();
            let exact_sq: f64 = d.iter().map(|x| x * x).sum();
            assert!(
                (sum - exact_sum).abs() <= 1e-12 * exact_sum,
                "{n} {range}: {sum} vs {exact_sum}"
            );
            assert!(
                (sum_sq - exact_sq).abs() <= 1e-12 * exact_sq,
                "{n} {range}: squares"
            );
            assert_eq!(max, d.iter().copied().fold(0.0, f64::max));
        }
    }

    #[test]
    fn a_term_never_exceeds_its_cap_so_no_sum_overflows() {
        // The largest grid (2¹⁴ × 2¹⁴ points) of errors at the largest possible value, an
        // overflowing square, and heights far beyond any real data: N terms still fit in u64.
        let n = 1usize << 28;
        for range in [0.0, 1e-300, 1.0, 8.0, 1e150, 1e300, f64::MAX] {
            let units = ErrorUnits::new(n, range);
            for d in [range, range * (1.0 + 1e-15), f64::MAX, f64::INFINITY] {
                for term in [units.units(d), units.units_sq(d)] {
                    assert!(term.checked_mul(n as u64).is_some(), "{range} {d}");
                }
            }
        }
        // A power-of-two range is its own bound: the largest error is exactly the largest term.
        let units = ErrorUnits::new(4, 8.0);
        assert_eq!(units.units(8.0), 1 << 51);
        assert_eq!(units.value(units.units(8.0)), 8.0);
        assert_eq!(units.units(0.0), 0);
    }
}
