//! Code shared by the integration tests: for the evaluator's (`tests/incremental.rs`,
//! `tests/compose.rs`) fixtures, synthetic grids, random kept sets and scores as bits; for
//! those that run the binary, [`cli`]. Each test file uses a part of it.
#![allow(dead_code)]

pub mod cli;

use paretomesh::evaluator::Score;
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::path::Path;
use std::sync::Arc;

/// The fixture `tests/data/{name}.f32`.
pub fn fixture(name: &str) -> Arc<Heightfield> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(format!("{name}.f32"));
    Arc::new(import::load(&path).expect("fixture"))
}

/// A grid of integer-valued heights (many exact ties in the interpolation) for even seeds, or
/// random reals for odd ones.
pub fn synthetic(width: usize, height: usize, seed: u64) -> Arc<Heightfield> {
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
pub fn bits(s: Score) -> (u64, u64, u64, usize) {
    (s.e_sum.to_bits(), s.e_max.to_bits(), s.rms.to_bits(), s.t)
}

/// Each of the `n` grid points with probability `density`.
pub fn random_kept(n: usize, density: f64, rng: &mut Pcg64Mcg) -> Vec<u32> {
    (0..n as u32)
        .filter(|_| rng.random::<f64>() < density)
        .collect()
}
