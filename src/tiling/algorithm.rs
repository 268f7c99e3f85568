//! The one place the tiling builds an optimizer from an algorithm's name, its parameters as
//! JSON (as front.json records them) and a seed.

use super::{TilePlan, TilingError};
use crate::catalogue::{Algorithm, Config};
use crate::evolution::memetic::search_budget;
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

/// The parameters every tile of `plan` runs `algorithm` with, from the run's `params` (as
/// [`build_optimizer`] takes them). The memetic method, unless given a budget
/// (`max_evaluations` or `search_evaluations`), searches for the whole grid's search budget
/// ([`search_budget`] of W·H points) shared evenly among the tiles, on top of each tile's own
/// seeding: the sweeps and the decimation, which give a tile's front nearly all its quality at
/// the triangle counts the whole-grid front combines tiles at, grow with the tile, while the
/// search, whose gains are mostly on a front's sparsest meshes, then costs as much in a tiled
/// run as in an untiled one. A one-tile plan gets the untiled budget. Other methods' parameters
/// are returned as given.
pub fn tile_params(
    plan: &TilePlan,
    algorithm: &str,
    params: &serde_json::Value,
) -> serde_json::Value {
    let budgeted = |key: &str| params.get(key).is_some_and(|v| !v.is_null());
    let memetic = Algorithm::from_name(algorithm) == Some(Algorithm::Memetic);
    if !memetic || budgeted("max_evaluations") || budgeted("search_evaluations") {
        return params.clone();
    }
    let mut out = match params {
        serde_json::Value::Object(map) => map.clone(),
        serde_json::Value::Null => serde_json::Map::new(),
        // Refused by `build_optimizer` with its own message.
        _ => return params.clone(),
    };
    let points = (plan.width() * plan.height()) as u64;
    let share = search_budget(points).div_ceil(plan.len().max(1) as u64);
    out.insert("search_evaluations".to_string(), share.into());
    serde_json::Value::Object(out)
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
