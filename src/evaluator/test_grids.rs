//! Grids and kept sets shared by the evaluator's unit tests.

use super::Score;
use crate::heightfield::Heightfield;
use crate::import;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::path::Path;
use std::sync::Arc;

/// The height field `tests/data/{name}.f32`.
pub(crate) fn fixture(name: &str) -> Heightfield {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(format!("{name}.f32"));
    import::load(&path).unwrap()
}

/// Each of the `n` grid points, kept with probability `fraction`.
pub(crate) fn random_subset(n: usize, fraction: f64, rng: &mut Pcg64Mcg) -> Vec<u32> {
    (0..n as u32)
        .filter(|_| rng.random::<f64>() < fraction)
        .collect()
}

/// [`fixture`], shared as the evaluator holds it.
pub(crate) fn shared_fixture(name: &str) -> Arc<Heightfield> {
    Arc::new(fixture(name))
}

/// A grid of integer-valued heights (many exact ties in the interpolation) for even seeds, or
/// random reals for odd ones.
pub(crate) fn synthetic(width: usize, height: usize, seed: u64) -> Arc<Heightfield> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let z = (0..width * height)
        .map(|_| {
            if seed.is_multiple_of(2) {
                rng.random_range(0..5) as f64
            } else {
                rng.random::<f64>() * 100.0 - 50.0
            }
        })
        .collect();
    Arc::new(Heightfield::new(width, height, z).unwrap())
}

/// A score as exact bits, to compare with `assert_eq!`.
pub(crate) fn bits(s: Score) -> (u64, u64, u64, usize) {
    (s.e_sum.to_bits(), s.e_max.to_bits(), s.rms.to_bits(), s.t)
}
