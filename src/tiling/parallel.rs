//! Every tile of a plan run on a pool of threads (native builds only).

use super::assemble::{TiledFront, assemble};
use super::tile_front::{TileFront, run_tile};
use super::{TilePlan, TilingError};
use crate::heightfield::Heightfield;
use rayon::prelude::*;

/// Runs every tile of `plan` on `hf` with `algorithm`, `params` and `seed` on `threads` threads
/// (0 = every core) and assembles the whole-grid front. Each tile is a pure function of its
/// inputs and the tiles are assembled in index order, so the front has the same bits for any
/// number of threads.
pub fn run_tiled(
    hf: &Heightfield,
    plan: &TilePlan,
    algorithm: &str,
    params: &serde_json::Value,
    seed: u64,
    threads: usize,
) -> Result<TiledFront, TilingError> {
    run_tiled_with_progress(hf, plan, algorithm, params, seed, threads, &|_| {})
}

/// [`run_tiled`], calling `done(tile index)` as each tile finishes (from the thread that ran
/// it, in any order).
pub fn run_tiled_with_progress(
    hf: &Heightfield,
    plan: &TilePlan,
    algorithm: &str,
    params: &serde_json::Value,
    seed: u64,
    threads: usize,
    done: &(dyn Fn(usize) + Sync),
) -> Result<TiledFront, TilingError> {
    plan.check_grid(hf)?;
    // Fail on a bad algorithm or parameters before any tile's long run.
    let probe = plan.cut(hf, 0)?;
    super::algorithm::build_optimizer(std::sync::Arc::new(probe), algorithm, params, seed)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| TilingError::Threads(e.to_string()))?;
    let fronts: Vec<TileFront> = pool.install(|| {
        (0..plan.len())
            .into_par_iter()
            .map(|index| {
                let tile_hf = plan.cut(hf, index)?;
                let front = run_tile(&tile_hf, plan, index, algorithm, params, seed)?;
                done(index);
                Ok(front)
            })
            .collect::<Result<Vec<_>, TilingError>>()
    })?;
    assemble(plan, fronts)
}
