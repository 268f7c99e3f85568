//! Summing one row span's errors into fixed-point totals, a kernel per instruction set.
//!
//! A span is `len` consecutive grid points of one row with z̃ = start + k·step at its k-th
//! point. Every kernel computes each point's error with the scalar formula's operations in the
//! scalar formula's order (k·step, then start + that, then z − z̃, then |·|), and rounds it
//! to the same fixed-point integers ([`ErrorUnits`]), so every kernel gives the same totals, bit
//! for bit; they differ only in how many points go through one instruction.
//!
//! Why vectors: at 2 % kept a span holds ≈2.8 points and a loop over them mispredicts its exit
//! about once per span, which costs more than the points. The AVX2 kernel takes any span of up
//! to eight points in two fixed four-lane steps (lanes past its end get an error of 0, which
//! adds nothing), so a sparse mesh's rows run without a data-dependent branch.
//!
//! Each lane sums the *raw* bits of its rounded terms (x + 2⁵², see [`ErrorUnits::units`]) with
//! wrapping, and the totals remove 2⁵²'s bits once per lane-point: every true sum is below 2⁶²,
//! so the wrapping sums are exact.

#[cfg(target_arch = "x86_64")]
use crate::evaluator::exact::fixed_point::ROUNDER;
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};

/// A way to sum spans (see the module docs). `Sums` are one triangle's running sums, `Step` a
/// triangle's per-span constants.
pub trait Kernel: Copy {
    /// Running sums.
    type Sums: Copy;
    /// What a triangle's spans share: its step, as the kernel wants it.
    type Step: Copy;
    /// Empty sums.
    fn sums(&self) -> Self::Sums;
    /// The per-triangle constants for z̃'s step along a row.
    fn step(&self, step: f64) -> Self::Step;
    /// Adds |z\[k\] − (start + k·step)| for k in `0..len` (`len` ≤ 0: nothing). `z` starts at the
    /// span's first point and holds at least `len` heights.
    fn add_span(&self, sums: &mut Self::Sums, step: &Self::Step, z: &[f64], len: i64, start: f64);
    /// The totals of `sums`.
    fn totals(&self, sums: &Self::Sums) -> ErrorTotals;
}

/// One point at a time: every target.
#[derive(Clone, Copy, Debug)]
pub struct Scalar(pub ErrorUnits);

impl Kernel for Scalar {
    type Sums = ErrorTotals;
    type Step = f64;

    #[inline(always)]
    fn sums(&self) -> ErrorTotals {
        ErrorTotals::default()
    }

    #[inline(always)]
    fn step(&self, step: f64) -> f64 {
        step
    }

    #[inline(always)]
    fn add_span(&self, sums: &mut ErrorTotals, &step: &f64, z: &[f64], len: i64, start: f64) {
        if len <= 0 {
            return;
        }
        for (k, &zk) in z[..len as usize].iter().enumerate() {
            // An i32 counter converts to f64 in one instruction (a usize in a branchy sequence).
            sums.add_error(self.0, (zk - (start + k as i32 as f64 * step)).abs());
        }
    }

    #[inline(always)]
    fn totals(&self, sums: &ErrorTotals) -> ErrorTotals {
        *sums
    }
}

#[cfg(target_arch = "x86_64")]
pub use avx2::Avx2;

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{ErrorTotals, ErrorUnits, Kernel, ROUNDER, Scalar};
    use core::arch::x86_64::*;

    /// Four lanes of f64 (AVX2). Only to be used inside a function compiled with the `avx2`
    /// target feature, on a CPU that has it ([`Avx2::detect`]).
    #[derive(Clone, Copy, Debug)]
    pub struct Avx2 {
        units: ErrorUnits,
        scale: __m256d,
        scale_sq: __m256d,
        cap: __m256d,
        rounder: __m256d,
        abs: __m256d,
    }

    /// Four-lane running sums.
    #[derive(Clone, Copy, Debug)]
    pub struct Sums {
        sum: __m256i,
        sum_sq: __m256i,
        max: __m256d,
        /// Lane-points added.
        count: u64,
        /// Points too near the end of the heights for a four-lane load.
        tail: ErrorTotals,
    }

    /// k·step for k = 0..8.
    #[derive(Clone, Copy, Debug)]
    pub struct Step {
        step: f64,
        low: __m256d,
        high: __m256d,
    }

    impl Avx2 {
        /// The kernel for `units` when this CPU has AVX2.
        pub fn detect(units: ErrorUnits) -> Option<Self> {
            if !std::arch::is_x86_feature_detected!("avx2") {
                return None;
            }
            // SAFETY: AVX is present (AVX2 implies it).
            unsafe { Some(Self::new(units)) }
        }

        #[target_feature(enable = "avx2")]
        unsafe fn new(units: ErrorUnits) -> Self {
            Self {
                units,
                scale: _mm256_set1_pd(units.scale),
                scale_sq: _mm256_set1_pd(units.scale_sq),
                cap: _mm256_set1_pd(units.cap),
                rounder: _mm256_set1_pd(ROUNDER),
                abs: _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX)),
            }
        }

        /// Four lanes: z at `p` (lanes where `mask` is clear are not read), z̃ = start + kstep.
        #[inline(always)]
        unsafe fn quad(
            &self,
            sums: &mut Sums,
            p: *const f64,
            mask: __m256i,
            start: __m256d,
            kstep: __m256d,
        ) {
            // SAFETY (all intrinsics): the caller runs with AVX2; the masked load reads only
            // the lanes its mask selects, which the caller keeps within the heights.
            unsafe {
                let z = _mm256_maskload_pd(p, mask);
                let zt = _mm256_add_pd(start, kstep);
                let d = _mm256_and_pd(_mm256_sub_pd(z, zt), self.abs);
                // Lanes past the span's end: error 0, which adds nothing.
                let d = _mm256_and_pd(d, _mm256_castsi256_pd(mask));
                // min(x, cap) + 2⁵² (x is never NaN, so minpd is `at_most`).
                let t = _mm256_add_pd(
                    _mm256_min_pd(_mm256_mul_pd(d, self.scale), self.cap),
                    self.rounder,
                );
                let q = _mm256_add_pd(
                    _mm256_min_pd(_mm256_mul_pd(_mm256_mul_pd(d, d), self.scale_sq), self.cap),
                    self.rounder,
                );
                sums.sum = _mm256_add_epi64(sums.sum, _mm256_castpd_si256(t));
                sums.sum_sq = _mm256_add_epi64(sums.sum_sq, _mm256_castpd_si256(q));
                sums.max = _mm256_max_pd(d, sums.max);
                sums.count += 4;
            }
        }
    }

    impl Kernel for Avx2 {
        type Sums = Sums;
        type Step = Step;

        #[inline(always)]
        fn sums(&self) -> Sums {
            // SAFETY: see `Avx2`: used only where AVX2 is enabled and present.
            unsafe {
                Sums {
                    sum: _mm256_setzero_si256(),
                    sum_sq: _mm256_setzero_si256(),
                    max: _mm256_setzero_pd(),
                    count: 0,
                    tail: ErrorTotals::default(),
                }
            }
        }

        #[inline(always)]
        fn step(&self, step: f64) -> Step {
            // SAFETY: see `Avx2`.
            unsafe {
                let s = _mm256_set1_pd(step);
                Step {
                    step,
                    low: _mm256_mul_pd(_mm256_set_pd(3.0, 2.0, 1.0, 0.0), s),
                    high: _mm256_mul_pd(_mm256_set_pd(7.0, 6.0, 5.0, 4.0), s),
                }
            }
        }

        #[inline(always)]
        fn add_span(&self, sums: &mut Sums, step: &Step, z: &[f64], len: i64, start: f64) {
            if len <= 0 {
                return;
            }
            if (len as usize) > z.len() {
                // Cannot happen for a span of the grid; keeps the masked loads in bounds.
                Scalar(self.units).add_span(&mut sums.tail, &step.step, z, len, start);
                return;
            }
            // SAFETY: see `Avx2`; every lane a mask selects is below `len` ≤ z.len().
            unsafe {
                let p = z.as_ptr();
                let startv = _mm256_set1_pd(start);
                let lane = _mm256_set_epi64x(3, 2, 1, 0);
                if len <= 4 {
                    // Most spans of a sparse mesh's triangles (a 2 %-kept grid's average ≈ 3.5).
                    let low = _mm256_cmpgt_epi64(_mm256_set1_epi64x(len), lane);
                    self.quad(sums, p, low, startv, step.low);
                } else if len <= 8 {
                    let lenv = _mm256_set1_epi64x(len);
                    let low = _mm256_cmpgt_epi64(lenv, lane);
                    let high =
                        _mm256_cmpgt_epi64(lenv, _mm256_add_epi64(lane, _mm256_set1_epi64x(4)));
                    self.quad(sums, p, low, startv, step.low);
                    self.quad(sums, p.add(4), high, startv, step.high);
                } else {
                    let s = _mm256_set1_pd(step.step);
                    let lenv = _mm256_set1_epi64x(len);
                    let mut k = 0i64;
                    while k < len {
                        let idx = _mm256_add_epi64(lane, _mm256_set1_epi64x(k));
                        let mask = _mm256_cmpgt_epi64(lenv, idx);
                        let kf =
                            _mm256_set_pd((k + 3) as f64, (k + 2) as f64, (k + 1) as f64, k as f64);
                        self.quad(sums, p.add(k as usize), mask, startv, _mm256_mul_pd(kf, s));
                        k += 4;
                    }
                }
            }
        }

        #[inline(always)]
        fn totals(&self, sums: &Sums) -> ErrorTotals {
            let mut sum = [0u64; 4];
            let mut sum_sq = [0u64; 4];
            let mut max = [0f64; 4];
            // SAFETY: see `Avx2`; unaligned stores into local arrays of the right size.
            unsafe {
                _mm256_storeu_si256(sum.as_mut_ptr().cast(), sums.sum);
                _mm256_storeu_si256(sum_sq.as_mut_ptr().cast(), sums.sum_sq);
                _mm256_storeu_pd(max.as_mut_ptr(), sums.max);
            }
            let bias = sums.count.wrapping_mul(ROUNDER.to_bits());
            let fold = |v: [u64; 4]| {
                v.iter()
                    .fold(0u64, |a, &x| a.wrapping_add(x))
                    .wrapping_sub(bias)
            };
            let pick = |a: f64, b: f64| if a > b { a } else { b };
            let mut t = ErrorTotals {
                sum: fold(sum),
                sum_sq: fold(sum_sq),
                max: pick(pick(max[0], max[1]), pick(max[2], max[3])),
            };
            t.add(&sums.tail);
            t
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// Sums every span of `z` (each `(first, len, start, step)`) with kernel `k`.
    fn sum_with<K: Kernel>(k: K, z: &[f64], spans: &[(usize, i64, f64, f64)]) -> ErrorTotals {
        let mut all = ErrorTotals::default();
        for &(first, len, start, step) in spans {
            let mut sums = k.sums();
            k.add_span(&mut sums, &k.step(step), &z[first..], len, start);
            all.add(&k.totals(&sums));
        }
        all
    }

    #[test]
    fn every_kernel_gives_the_scalar_bits() {
        // Spans of every length from empty to past the eight-lane fast case, some ending at the
        // last height (where a four-lane load would read past the slice), on heights of mixed
        // scales: each kernel this CPU runs must give the scalar kernel's integers exactly.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x5eed);
        for round in 0..200 {
            let n = 1 + rng.random_range(0..60);
            let scale = [1e-3, 1.0, 83.5, 4096.0][round % 4];
            let z: Vec<f64> = (0..n).map(|_| scale * rng.random::<f64>()).collect();
            let units = ErrorUnits::new(n, scale);
            let spans: Vec<(usize, i64, f64, f64)> = (0..30)
                .map(|_| {
                    let first = rng.random_range(0..n);
                    let len = if rng.random_range(0..4) == 0 {
                        (n - first) as i64
                    } else {
                        rng.random_range(-1..=(n - first).min(20) as i64)
                    };
                    let start = scale * rng.random::<f64>();
                    let step = scale * (rng.random::<f64>() - 0.5) * 0.1;
                    (first, len, start, step)
                })
                .collect();
            let expected = sum_with(Scalar(units), &z, &spans);
            #[cfg(target_arch = "x86_64")]
            if let Some(k) = Avx2::detect(units) {
                let got = sum_with(k, &z, &spans);
                assert_eq!(got.sum, expected.sum, "round {round}");
                assert_eq!(got.sum_sq, expected.sum_sq, "round {round}");
                assert_eq!(got.max.to_bits(), expected.max.to_bits(), "round {round}");
            }
            // The scalar kernel is the point-by-point definition.
            let mut direct = ErrorTotals::default();
            for &(first, len, start, step) in &spans {
                for k in 0..len.max(0) as usize {
                    direct.add_error(units, (z[first + k] - (start + k as f64 * step)).abs());
                }
            }
            assert_eq!(expected, direct, "round {round}");
        }
    }
}
