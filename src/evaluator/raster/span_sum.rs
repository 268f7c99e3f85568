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

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "x86_64")]
    use crate::evaluator::raster::span_sum_avx2::Avx2;
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
