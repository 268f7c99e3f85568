//! The span kernels against each other: every kernel this CPU runs gives the scalar kernel's
//! bits, and the scalar kernel is the point-by-point definition. Beside both kernels, so that
//! neither file imports the other's twin.

use super::span_sum::{Kernel, Scalar};
#[cfg(target_arch = "x86_64")]
use super::span_sum_avx2::Avx2;
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
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
