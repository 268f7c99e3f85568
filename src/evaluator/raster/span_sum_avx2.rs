//! The AVX2 twin of [`span_sum::Scalar`](super::span_sum::Scalar): four points of a span per
//! instruction, the same fixed-point totals bit for bit.

use super::span_sum::{Kernel, Scalar};
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits, ROUNDER};
use core::arch::x86_64::*;

/// Four lanes of f64 (AVX2). Only to be used inside a function compiled with the `avx2`
/// target feature, on a CPU that has it ([`Avx2::detect`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2 {
    units: ErrorUnits,
    scale: __m256d,
    scale_sq: __m256d,
    cap: __m256d,
    rounder: __m256d,
    abs: __m256d,
}

/// Four-lane running sums.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sums {
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
pub(crate) struct Step {
    step: f64,
    low: __m256d,
    high: __m256d,
}

impl Avx2 {
    /// The kernel for `units` when this CPU has AVX2.
    pub(crate) fn detect(units: ErrorUnits) -> Option<Self> {
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
                let high = _mm256_cmpgt_epi64(lenv, _mm256_add_epi64(lane, _mm256_set1_epi64x(4)));
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
