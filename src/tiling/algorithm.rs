//! A tile's method: the run's [`Config`] with the tile's share of its budget, built on the
//! tile's grid, and the tile's seed.

use super::{TilePlan, TilingError};
use crate::catalogue::{Config, Running};
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// The method every tile of `plan` runs, from the run's `config`: the catalogue's
/// `Config::tile_share` for a grid of the plan's W·H points cut into its tiles (the memetic
/// search's share of the whole grid's budget; other methods as given). Sharing a shared
/// config changes nothing, so the recorded config and the tiles' agree.
pub fn tile_config(plan: &TilePlan, config: &Config) -> Config {
    let points = (plan.width() * plan.height()) as u64;
    config.clone().tile_share(points, plan.len())
}

/// The optimizer of tile `index` of `plan`, whose own grid is `hf`: `config` (its tile share,
/// [`tile_config`]) with the tile's seed. Errors: the grid is not the tile's, or the method
/// refuses its parameters.
pub(crate) fn build_tile(
    hf: Arc<Heightfield>,
    plan: &TilePlan,
    index: usize,
    config: &Config,
    seed: u64,
) -> Result<Box<dyn Running>, TilingError> {
    let tile = plan.tile(index).ok_or(TilingError::NoSuchTile {
        index,
        tiles: plan.len(),
    })?;
    if (hf.width(), hf.height()) != (tile.w, tile.h) {
        return Err(TilingError::GridMismatch {
            plan: (tile.w, tile.h),
            grid: (hf.width(), hf.height()),
        });
    }
    let config = tile_config(plan, config);
    let algorithm = config.algorithm();
    let built = config
        .build(hf, tile_seed(seed, index))
        .map_err(|reason| TilingError::BadParams { algorithm, reason })?;
    Ok(built.optimizer)
}

/// The seed of tile `index` in a run with `seed`: a SplitMix64 mix of both, so neighbouring
/// tiles (and runs) get unrelated streams wherever the tile runs.
pub(crate) fn tile_seed(seed: u64, index: usize) -> u64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    mix(seed ^ mix(index as u64))
}
