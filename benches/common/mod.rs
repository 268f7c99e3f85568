//! Grids for the benches, so that they run from a fresh clone: fixtures from `tests/data`, and a
//! larger terrain generated here.

// Each bench includes this module and uses part of it.
#![allow(dead_code)]

use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use rand::{RngExt, SeedableRng};
use std::path::Path;

/// A fixture from `tests/data` by name (`jacksboro_65x65` reads `tests/data/jacksboro_65x65.f32`).
pub fn fixture(name: &str) -> Heightfield {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/{name}.f32"));
    import::load(&path).unwrap_or_else(|e| panic!("fixture {name}: {e}"))
}

/// The side of the benches' large generated grid: 257, or 65 when the bench runs as a test.
/// `cargo test --all-targets` (CI) runs every bench once to check that it works, in a debug
/// build, where greedy insertion and decimation of 257×257 points take most of a minute; the
/// check needs only that the code runs. `cargo bench` passes `--bench`.
pub fn large_size() -> usize {
    if std::env::args().any(|a| a == "--bench") {
        257
    } else {
        65
    }
}

/// The name of [`synthetic_terrain`]'s grid of `size`×`size` points, as the benches report it.
pub fn synthetic_name(size: usize) -> String {
    format!("synthetic_{size}x{size}")
}

/// A `size`×`size` terrain that stands in for a real DEM: a few broad hills and a ridge (smooth
/// at the scale of the grid, so a simplified mesh can follow them) plus fine seeded noise (so
/// that, as in measured data, every point carries some error). Deterministic: the same grid
/// on every machine.
pub fn synthetic_terrain(size: usize) -> Heightfield {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(2024);
    let hills: Vec<[f64; 4]> = (0..6)
        .map(|_| {
            [
                rng.random::<f64>(),               // centre x, as a fraction of the grid
                rng.random::<f64>(),               // centre y
                0.05 + 0.15 * rng.random::<f64>(), // radius
                20.0 + 80.0 * rng.random::<f64>(), // height
            ]
        })
        .collect();
    let mut z = Vec::with_capacity(size * size);
    for y in 0..size {
        for x in 0..size {
            let (u, v) = (x as f64 / (size - 1) as f64, y as f64 / (size - 1) as f64);
            let mut h = 30.0 * (u * 3.0 + v * 1.5).sin() * (1.0 - (v - 0.5).abs());
            for &[cx, cy, r, a] in &hills {
                let d2 = (u - cx).powi(2) + (v - cy).powi(2);
                h += a * (-d2 / (r * r)).exp();
            }
            h += 2.0 * (rng.random::<f64>() - 0.5);
            z.push(h);
        }
    }
    Heightfield::new(size, size, z)
        .expect("a generated grid is valid")
        .with_source(format!("{} (generated)", synthetic_name(size)))
}

/// `fraction` of the `n` grid points, chosen at random with a fixed seed, plus `corners`,
/// sorted: a kept set as the GAs' chromosomes are.
pub fn kept_subset(n: usize, fraction: f64, seed: u64, corners: [u32; 4]) -> Vec<u32> {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    let mut kept: Vec<u32> = (0..n as u32)
        .filter(|_| rng.random::<f64>() < fraction)
        .collect();
    kept.extend(corners);
    kept.sort_unstable();
    kept.dedup();
    kept
}
