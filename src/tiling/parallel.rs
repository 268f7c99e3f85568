//! Every tile of a plan run on a pool of threads (native builds only).

use super::algorithm::build_tile;
use super::assemble::{TiledFront, assemble};
use super::tile_front::{MEMBERS_PER_TILE, TileFront, run_built_tile};
use super::{TilePlan, TileSource, TilingError};
use crate::catalogue::Config;
use crate::heightfield::Heightfield;
use rayon::prelude::*;
use std::sync::{Arc, Mutex};

/// Runs every tile of `plan` on `hf` with `config` and `seed` on `threads` threads (0 = every
/// core) and assembles the whole-grid front. Each tile is a pure function of its inputs and the
/// tiles are assembled in index order, so the front has the same bits for any number of
/// threads.
pub fn run_tiled(
    hf: &Heightfield,
    plan: &TilePlan,
    config: &Config,
    seed: u64,
    threads: usize,
) -> Result<TiledFront, TilingError> {
    run_tiled_with_progress(hf, plan, config, seed, threads, &|_| {})
}

/// [`run_tiled`] on any [`TileSource`], calling `done(tile index)` as each tile finishes
/// (from the thread that ran it, in any order). Each tile's grid is made when the tile starts
/// and dropped when its front is made, so a source that reads windows (a grid file's) holds
/// only the tiles in flight; the front is the same for every source of the same grid.
pub fn run_tiled_with_progress(
    hf: &dyn TileSource,
    plan: &TilePlan,
    config: &Config,
    seed: u64,
    threads: usize,
    done: &(dyn Fn(usize) + Sync),
) -> Result<TiledFront, TilingError> {
    plan.check_size(hf.size())?;
    // Tile 0's optimizer is built first, so that parameters its method refuses fail the run
    // before any tile's long run; it is then the one tile 0 runs.
    let first = Arc::new(hf.cut(plan, 0)?);
    let built = build_tile(first.clone(), plan, 0, config, seed)?;
    let first = Mutex::new(Some((first, built)));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| TilingError::Threads(e.to_string()))?;
    let fronts: Vec<TileFront> = pool.install(|| {
        (0..plan.len())
            .into_par_iter()
            .map(|index| {
                let taken = if index == 0 {
                    first.lock().ok().and_then(|mut f| f.take())
                } else {
                    None
                };
                let (tile_hf, optimizer) = match taken {
                    Some(started) => started,
                    None => {
                        let tile_hf = Arc::new(hf.cut(plan, index)?);
                        let optimizer = build_tile(tile_hf.clone(), plan, index, config, seed)?;
                        (tile_hf, optimizer)
                    }
                };
                let front = run_built_tile(tile_hf, optimizer, plan, index, MEMBERS_PER_TILE)?;
                done(index);
                Ok(front)
            })
            .collect::<Result<Vec<_>, TilingError>>()
    })?;
    assemble(plan, fronts)
}
