//! The one place the tiling builds an optimizer from an algorithm's name, its parameters as
//! JSON (as front.json records them) and a seed.

use super::TilingError;
use crate::catalogue::{Algorithm, Config};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use std::sync::Arc;

/// An optimizer `algorithm` (a catalogue name) on `hf` with `params` (its params type as
/// JSON; `null` for the defaults) and `seed` (ignored by the deterministic methods).
pub fn build_optimizer(
    hf: Arc<Heightfield>,
    algorithm: &str,
    params: &serde_json::Value,
    seed: u64,
) -> Result<Box<dyn Optimizer>, TilingError> {
    let bad = |reason: String| TilingError::BadParams {
        algorithm: algorithm.to_string(),
        reason,
    };
    let method = Algorithm::from_name(algorithm)
        .ok_or_else(|| TilingError::UnknownAlgorithm(algorithm.to_string()))?;
    let built = Config::from_json(method, params)
        .map_err(bad)?
        .build(hf, seed)
        .map_err(bad)?;
    Ok(built.optimizer)
}

/// The seed of tile `index` in a run with `seed`: a SplitMix64 mix of both, so neighbouring
/// tiles (and runs) get unrelated streams wherever the tile runs.
pub fn tile_seed(seed: u64, index: usize) -> u64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    mix(seed ^ mix(index as u64))
}
