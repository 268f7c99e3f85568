//! `run --algo greedy --max-vertical-error X` on a tiled grid: one mesh within X, made over
//! the tiles in parallel with shared border points ([`tiled_mesh_within`]), written as a
//! tiled front of that one member.

use paretomesh::baselines::{GreedyStop, InsertionRule};
use paretomesh::catalogue::Config;
use paretomesh::heightfield::Heightfield;
use paretomesh::tiling::{TilePlan, TiledFront, tiled_mesh_within};
use std::time::Instant;

/// The tile size of a mesh within a max error when `--tile` is not given. Why smaller than a
/// front's: greedy insertion re-rasterises a point each time a triangle over it is split, and
/// smaller tiles start it from smaller triangles; on the 3601² fractal at hmm's E_max at 2 %,
/// tiles of 257 took 0.4× the CPU of tiles of 1025, with 1 % more triangles (fewer on the
/// urban grid).
pub(super) const WITHIN_TILE: usize = 257;

/// Whether a run of `config` makes one mesh within a max error (see [`stop_of`]); it takes
/// tiles of [`WITHIN_TILE`] when `--tile` is not given.
pub(super) fn makes_one_mesh(config: &Config) -> bool {
    stop_of(config).is_some()
}

/// The error stop of greedy insertion of the worst point with bounded-error decimation: the
/// runs that make one mesh within a max error over tiles (the other greedy rules and stops
/// give a front as any tiled method does).
fn stop_of(config: &Config) -> Option<GreedyStop> {
    let Config::Greedy(p) = config else {
        return None;
    };
    (p.rule == InsertionRule::MaxError && p.decimate).then_some(p.stop)
}

/// The max error X a tiled run of `config` on `hf` is one mesh within (see [`stop_of`]).
pub(super) fn bound_of(config: &Config, hf: &Heightfield) -> Option<f64> {
    let (lo, hi) = hf.z_range();
    match stop_of(config)? {
        GreedyStop::MaxError(x) => Some(x),
        GreedyStop::MaxErrorFraction(f) => Some(f * (hi - lo)),
        _ => None,
    }
}

/// The mesh within `x` over `plan`'s tiles on `threads` threads, as a one-member tiled front,
/// with a `done:` line on stderr.
pub(super) fn make(
    hf: &Heightfield,
    plan: &TilePlan,
    x: f64,
    threads: usize,
) -> Result<TiledFront, String> {
    let started = Instant::now();
    let made = tiled_mesh_within(hf, plan, None, x, threads).map_err(|e| e.to_string())?;
    let m = &made.front.members[0];
    eprintln!(
        "done: {} evaluations in {} ms, one mesh within E_max ≤ {x}: T = {}, E_max = {}, E_sum = {} ({} points inserted by greedy insertion of the worst point, {} removed by bounded-error decimation, {} tiles with shared border points, {} round{})",
        made.inserted,
        started.elapsed().as_millis(),
        m.t,
        m.e_max,
        m.e_sum,
        made.inserted,
        made.removed,
        plan.len(),
        made.rounds,
        if made.rounds == 1 { "" } else { "s" }
    );
    Ok(made.front)
}
