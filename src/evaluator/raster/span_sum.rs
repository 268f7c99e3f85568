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
pub(crate) trait Kernel: Copy {
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
pub(crate) struct Scalar(pub ErrorUnits);

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
