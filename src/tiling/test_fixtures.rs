//! What the tiling's tests share (`tests.rs`, `measure_tests.rs`): a rough test grid, a tiled
//! run with every tile in turn, and random allocation instances with their brute force.

use super::allocation::TileOption;
use super::*;
use crate::catalogue::Config;
use crate::heightfield::Heightfield;

/// A rough, deterministic test grid: a few waves plus hashed noise, so that every point carries
/// some error and no two tilings tie.
pub(super) fn terrain(w: usize, h: usize, seed: u64) -> Heightfield {
    let z = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            let mut n = (i as u64 ^ seed).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            n ^= n >> 29;
            let noise = (n % 1000) as f64 / 1000.0;
            (x * 0.21).sin() * 5.0 + (y * 0.13 + x * 0.05).cos() * 3.0 + noise
        })
        .collect();
    Heightfield::new(w, h, z).unwrap()
}

/// `config` run on `hf` in tiles of `tile`, one tile after another (seed 7), and assembled.
pub(super) fn tiled(hf: &Heightfield, tile: usize, config: &Config) -> TiledFront {
    let plan = TilePlan::new(hf.width(), hf.height(), tile).unwrap();
    let fronts = (0..plan.len())
        .map(|i| run_tile(&plan.cut(hf, i).unwrap(), &plan, i, config, 7).unwrap())
        .collect();
    assemble(&plan, fronts).unwrap()
}

/// A small deterministic generator for the allocation instances.
pub(super) fn lcg(state: &mut u64) -> u64 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    *state >> 33
}

/// An allocation instance: 1 to 4 tiles of 1 to 6 options, small integer errors and T.
pub(super) fn random_options(rng: &mut u64) -> Vec<Vec<TileOption>> {
    let tiles = 1 + (lcg(rng) % 4) as usize;
    (0..tiles)
        .map(|_| {
            let n = 1 + (lcg(rng) % 6) as usize;
            (0..n)
                .map(|_| TileOption {
                    e: (lcg(rng) % 50) as f64,
                    e_max: (lcg(rng) % 9) as f64,
                    t: 2 + lcg(rng) % 20,
                })
                .collect()
        })
        .collect()
}

/// The (Σ E, largest E_max, Σ T) of `choice`, one option index a tile.
pub(super) fn sums(options: &[Vec<TileOption>], choice: &[usize]) -> (f64, f64, u64) {
    let chosen = || choice.iter().enumerate().map(|(i, &c)| &options[i][c]);
    (
        chosen().map(|o| o.e).sum(),
        chosen().map(|o| o.e_max).fold(0.0, f64::max),
        chosen().map(|o| o.t).sum(),
    )
}

/// Every way to choose one option a tile, each as its [`sums`]: the brute force that the
/// allocations are checked against.
pub(super) fn every_choice(options: &[Vec<TileOption>]) -> Vec<(f64, f64, u64)> {
    let mut all = Vec::new();
    let mut choice = vec![0usize; options.len()];
    'combinations: loop {
        all.push(sums(options, &choice));
        for k in 0..options.len() {
            choice[k] += 1;
            if choice[k] < options[k].len() {
                continue 'combinations;
            }
            choice[k] = 0;
        }
        return all;
    }
}
