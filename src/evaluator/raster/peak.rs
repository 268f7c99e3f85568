//! One pass over a triangle's points that gives both its error totals and its *peak*, the point
//! of largest error: what greedy insertion needs of every new triangle (the peak is its next
//! candidate, the totals make its recorded meshes' scores without rasterising them again).
//!
//! The errors are those of [`Grid::for_each_error`], bit for bit (each kernel computes them as
//! [`span_sum`](super::span_sum) does), so the peak's error is a fresh evaluation's E_max on that
//! triangle and the totals are [`Grid::sum_triangles`]'s. Among points of equal error the
//! smallest grid index is the peak: points are visited row by row upwards and left to right,
//! which is increasing index order, and only a strictly larger error displaces the peak.

use super::{Grid, RowSink, Spans};
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::exact::predicates::GridPoint;

/// "No point": the peak of a triangle that owns no grid point.
pub(crate) const NO_POINT: u32 = u32::MAX;

/// What one pass over the points a triangle owns gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Peak {
    /// The error totals ([`Grid::sum_triangles`]'s bits).
    pub totals: ErrorTotals,
    /// The grid index of the owned point of largest error (the smallest among equals; its
    /// error is `totals.max`), or [`NO_POINT`].
    pub at: u32,
    /// Σ |z − z̃| added up in f64 in visiting order, as a plain loop over
    /// [`Grid::for_each_error`] adds it (0 unless the finder was asked for it).
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
struct PeakRows<'a, K: PeakKernel> {
    z: &'a [f64],
    k: &'a K,
    s: &'a Spans,
    sums: K::Sums,
    step: K::Step,
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

/// The peak finder greedy insertion keeps: the fastest kernel this CPU has, chosen once.
#[derive(Clone, Copy, Debug)]
pub(crate) enum PeakFinder {
    /// Portable, without the f64 sum.
    Scalar(ScalarPeak<false>),
    /// Portable, with the f64 sum (which is a serial chain of additions: no vector kernel).
    FloatSum(ScalarPeak<true>),
    /// Four points per instruction, without the f64 sum.
    #[cfg(target_arch = "x86_64")]
    Avx2(super::peak_avx2::Avx2Peak),
}

impl PeakFinder {
    /// The finder for errors in `units`; `float_sum`: whether [`Peak::float_sum`] is wanted.
    pub(crate) fn new(units: ErrorUnits, float_sum: bool) -> Self {
        if float_sum {
            return Self::FloatSum(ScalarPeak(units));
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = super::peak_avx2::Avx2Peak::detect(units) {
            return Self::Avx2(k);
        }
        Self::Scalar(ScalarPeak(units))
    }

    /// The peak of each counter-clockwise triangle `tris` yields (vertices excluded), given to
    /// `done` with its key.
    pub(crate) fn peaks<Key>(
        &self,
        grid: &Grid<'_>,
        tris: impl IntoIterator<Item = (Key, [GridPoint; 3])>,
        done: impl FnMut(Key, Peak),
    ) {
        match *self {
            Self::Scalar(k) => grid.peaks_with(k, tris, done),
            Self::FloatSum(k) => grid.peaks_with(k, tris, done),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Avx2Peak::detect` found AVX2 on this CPU.
            Self::Avx2(k) => unsafe { grid.peaks_avx2(k, tris, done) },
        }
    }
}

impl Grid<'_> {
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn peaks_avx2<Key>(
        &self,
        k: super::peak_avx2::Avx2Peak,
        tris: impl IntoIterator<Item = (Key, [GridPoint; 3])>,
        done: impl FnMut(Key, Peak),
    ) {
        self.peaks_with(k, tris, done);
    }

    #[inline(always)]
    fn peaks_with<K: PeakKernel, Key>(
        &self,
        k: K,
        tris: impl IntoIterator<Item = (Key, [GridPoint; 3])>,
        mut done: impl FnMut(Key, Peak),
    ) {
        for (key, tri) in tris {
            let sums = match self.spans(tri) {
                None => k.sums(),
                Some(s) => {
                    let mut sink = PeakRows {
                        z: self.z,
                        k: &k,
                        s: &s,
                        sums: k.sums(),
                        step: k.step(s.gx),
                    };
                    s.rows(&mut sink);
                    sink.sums
                }
            };
            done(key, k.peak(&sums));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::exact::predicates::orient;
    use rand::{RngExt, SeedableRng};

    /// The peak, totals and f64 sum of `tri` from [`Grid::for_each_error`], point by point.
    fn by_definition(grid: &Grid<'_>, units: ErrorUnits, tri: [GridPoint; 3]) -> Peak {
        let mut totals = ErrorTotals::default();
        let (mut best, mut at, mut float_sum) = (-1.0, NO_POINT, 0.0);
        grid.for_each_error(tri, |i, d| {
            totals.add_error(units, d);
            float_sum += d;
            if d > best {
                (best, at) = (d, i as u32);
            }
        });
        Peak {
            totals,
            at,
            float_sum,
        }
    }

    #[test]
    fn every_peak_kernel_gives_the_pointwise_peak() {
        // Random triangles (slivers, flat tops and bottoms, edges on the border, large ones on
        // a bigger grid) on heights with many exact ties (small integers, so equal errors occur
        // and the smallest index must win): every kernel must give the point-by-point peak,
        // totals and (when asked) f64 sum, bit for bit.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x9ea4);
        let mut next = |bound: i64| rng.random_range(0..bound);
        let mut with_points = 0;
        for round in 0..6000 {
            let (w, h) = if round % 10 == 0 {
                (40 + next(30), 40 + next(30))
            } else {
                (2 + next(12), 2 + next(12))
            };
            let z: Vec<f64> = (0..w * h)
                .map(|i| match round % 3 {
                    0 => (i * 7 % 5) as f64,
                    1 => ((i * 37 % 11) as f64).sqrt() * 1.7 + (i % 5) as f64,
                    _ => 0.0,
                })
                .collect();
            let grid = Grid {
                width: w,
                height: h,
                z: &z,
            };
            let mut tri = [0; 3].map(|_| [next(w), next(h)]);
            match orient(tri[0], tri[1], tri[2]) {
                0 => continue,
                turn if turn < 0 => tri.swap(1, 2),
                _ => {}
            }
            let units = ErrorUnits::new((w * h) as usize, 12.0);
            let expected = by_definition(&grid, units, tri);
            with_points += usize::from(expected.at != NO_POINT);
            #[cfg(target_arch = "x86_64")]
            let avx2 = super::super::peak_avx2::Avx2Peak::detect(units).map(PeakFinder::Avx2);
            #[cfg(not(target_arch = "x86_64"))]
            let avx2 = None;
            let finders = [
                Some(PeakFinder::Scalar(ScalarPeak(units))),
                Some(PeakFinder::FloatSum(ScalarPeak(units))),
                Some(PeakFinder::new(units, false)),
                avx2,
            ];
            for finder in finders.into_iter().flatten() {
                let mut got = None;
                finder.peaks(&grid, [((), tri)], |_, p| got = Some(p));
                let got = got.unwrap();
                assert_eq!(got.at, expected.at, "round {round}: {tri:?} {finder:?}");
                assert_eq!(got.totals, expected.totals, "round {round}: {tri:?}");
                assert_eq!(got.totals.max.to_bits(), expected.totals.max.to_bits());
                if matches!(finder, PeakFinder::FloatSum(_)) {
                    assert_eq!(got.float_sum.to_bits(), expected.float_sum.to_bits());
                }
            }
        }
        assert!(with_points > 2000);
    }
}
