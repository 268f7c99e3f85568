//! Grids and kept sets shared by the evaluator's unit tests.

use crate::heightfield::Heightfield;
use crate::import;
use rand::RngExt;
use std::path::Path;

/// The height field `tests/data/{name}.f32`.
pub(crate) fn fixture(name: &str) -> Heightfield {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(format!("{name}.f32"));
    import::load(&path).unwrap()
}

/// Each of the `n` grid points, kept with probability `fraction`.
pub(crate) fn random_subset(n: usize, fraction: f64, rng: &mut rand_pcg::Pcg64Mcg) -> Vec<u32> {
    (0..n as u32)
        .filter(|_| rng.random::<f64>() < fraction)
        .collect()
}
