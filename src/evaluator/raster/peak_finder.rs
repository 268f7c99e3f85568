//! The peak finder greedy insertion keeps: the fastest [`peak`](super::peak) kernel this CPU
//! has, chosen once; apart from the kernels so that the AVX2 twin and the portable kernel it
//! builds on do not import each other.

use super::Grid;
use super::peak::{Peak, PeakKernel, PeakRows, ScalarPeak};
#[cfg(target_arch = "x86_64")]
use super::peak_avx2::Avx2Peak;
use crate::evaluator::exact::fixed_point::ErrorUnits;
use crate::evaluator::exact::predicates::GridPoint;

/// The peak finder greedy insertion keeps: the fastest kernel this CPU has, chosen once.
#[derive(Clone, Copy, Debug)]
pub(crate) enum PeakFinder {
    /// Portable, without the f64 sum.
    Scalar(ScalarPeak<false>),
    /// Portable, with the f64 sum (which is a serial chain of additions: no vector kernel).
    FloatSum(ScalarPeak<true>),
    /// Four points per instruction, without the f64 sum.
    #[cfg(target_arch = "x86_64")]
    Avx2(Avx2Peak),
}

impl PeakFinder {
    /// The finder for errors in `units`; `float_sum`: whether [`Peak::float_sum`] is wanted.
    pub(crate) fn new(units: ErrorUnits, float_sum: bool) -> Self {
        if float_sum {
            return Self::FloatSum(ScalarPeak(units));
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = Avx2Peak::detect(units) {
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
        k: Avx2Peak,
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
    use crate::evaluator::exact::fixed_point::ErrorTotals;
    use crate::evaluator::exact::predicates::orient;
    use crate::evaluator::raster::peak::NO_POINT;
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
            let avx2 = Avx2Peak::detect(units).map(PeakFinder::Avx2);
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
