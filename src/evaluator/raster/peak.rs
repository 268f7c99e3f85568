//! One pass over a triangle's points that gives both its error totals and its *peak*, the point
//! of largest error: what greedy insertion needs of every new triangle (the peak is its next
//! candidate, the totals make its recorded meshes' scores without rasterising them again).
//!
//! The errors are those of [`Grid::for_each_error`](super::Grid::for_each_error), bit for bit (each kernel computes them as
//! [`span_sum`](super::span_sum) does), so the peak's error is a fresh evaluation's E_max on that
//! triangle and the totals are [`Grid::sum_triangles`](super::Grid::sum_triangles)'s. Among points of equal error the
//! smallest grid index is the peak: points are visited row by row upwards and left to right,
//! which is increasing index order, and only a strictly larger error displaces the peak.

use super::{RowSink, Spans};
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};

/// "No point": the peak of a triangle that owns no grid point.
pub(crate) const NO_POINT: u32 = u32::MAX;

/// What one pass over the points a triangle owns gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Peak {
    /// The error totals ([`Grid::sum_triangles`](super::Grid::sum_triangles)'s bits).
    pub totals: ErrorTotals,
    /// The grid index of the owned point of largest error (the smallest among equals; its
    /// error is `totals.max`), or [`NO_POINT`].
    pub at: u32,
    /// Σ |z − z̃| added up in f64 in visiting order, as a plain loop over
    /// [`Grid::for_each_error`](super::Grid::for_each_error) adds it (0 unless the finder was asked for it).
    pub float_sum: f64,
}

/// A way to find peaks (see the module docs): the running state of one triangle's points and
/// what its spans share.
pub(crate) trait PeakKernel: Copy {
    /// Running sums and peak.
    type Sums: Copy;
    /// A triangle's per-span constants for z̃'s step along a row.
    type Step: Copy;
    /// Nothing seen yet.
    fn sums(&self) -> Self::Sums;
    /// The constants for a triangle whose z̃ grows by `step` per column.
    fn step(&self, step: f64) -> Self::Step;
    /// Adds the points `first..first + len` (`len` ≤ 0: none), whose heights `z` starts with,
    /// with z̃ = start + k·step at the k-th.
    fn add_span(
        &self,
        sums: &mut Self::Sums,
        step: &Self::Step,
        z: &[f64],
        first: usize,
        len: i64,
        start: f64,
    );
    /// The result.
    fn peak(&self, sums: &Self::Sums) -> Peak;
}

/// One point at a time, on every target; with `FLOAT_SUM`, also the f64 sum.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ScalarPeak<const FLOAT_SUM: bool>(pub ErrorUnits);

/// The scalar kernel's running state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ScalarSums {
    totals: ErrorTotals,
    /// The peak's error, −1 before the first point (so that the first point, of error ≥ 0,
    /// becomes the peak).
    best: f64,
    at: u32,
    float_sum: f64,
}

impl<const FLOAT_SUM: bool> PeakKernel for ScalarPeak<FLOAT_SUM> {
    type Sums = ScalarSums;
    type Step = f64;

    #[inline(always)]
    fn sums(&self) -> ScalarSums {
        ScalarSums {
            totals: ErrorTotals::default(),
            best: -1.0,
            at: NO_POINT,
            float_sum: 0.0,
        }
    }

    #[inline(always)]
    fn step(&self, step: f64) -> f64 {
        step
    }

    #[inline(always)]
    fn add_span(
        &self,
        sums: &mut ScalarSums,
        &step: &f64,
        z: &[f64],
        first: usize,
        len: i64,
        start: f64,
    ) {
        if len <= 0 {
            return;
        }
        for (k, &zk) in z[..len as usize].iter().enumerate() {
            // The span_sum kernels' formula and order of operations.
            let d = (zk - (start + k as i32 as f64 * step)).abs();
            sums.totals.add_error(self.0, d);
            if d > sums.best {
                sums.best = d;
                sums.at = (first + k) as u32;
            }
            if FLOAT_SUM {
                sums.float_sum += d;
            }
        }
    }

    #[inline(always)]
    fn peak(&self, sums: &ScalarSums) -> Peak {
        Peak {
            totals: sums.totals,
            at: sums.at,
            float_sum: sums.float_sum,
        }
    }
}

/// The better of two peaks of disjoint point sets: the larger error, the smaller index on a
/// tie (so merging in any order gives the one-pass answer).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) fn better(a: (f64, u32), b: (f64, u32)) -> (f64, u32) {
    if b.0 > a.0 || (b.0 == a.0 && b.1 < a.1) {
        b
    } else {
        a
    }
}

/// Rows into a peak kernel.
pub(super) struct PeakRows<'a, K: PeakKernel> {
    pub(super) z: &'a [f64],
    pub(super) k: &'a K,
    pub(super) s: &'a Spans,
    pub(super) sums: K::Sums,
    pub(super) step: K::Step,
}

impl<K: PeakKernel> RowSink for PeakRows<'_, K> {
    #[inline(always)]
    fn row(&mut self, y: i64, lo: i64, hi: i64) {
        let first = y as usize * self.s.width + lo as usize;
        let z = &self.z[first.min(self.z.len())..];
        let start = self.s.start(y, lo);
        self.k
            .add_span(&mut self.sums, &self.step, z, first, hi - lo + 1, start);
    }
}
