//! One mesh within a max error, from a given start: greedy insertion of the worst point until
//! E_max ≤ X, then bounded-error decimation ([`bounded_decimation`](super::bounded_decimation)).
//! `export --max-vertical-error` uses it to reach a bound no member of a front meets tightly.

use super::ParamsError;
use super::greedy_insertion::{GreedyInsertion, GreedyParams, GreedyStop, InsertionRule};
use crate::evaluator::Score;
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use std::sync::Arc;

/// A mesh within a max error and how it was reached.
#[derive(Clone, Debug, PartialEq)]
pub struct MaxErrorMesh {
    /// Its kept grid indices, increasing.
    pub kept: Vec<u32>,
    /// Its score: the evaluator's bits for `kept`, with `e_max` ≤ the bound.
    pub score: Score,
    /// Points greedy insertion added to the start.
    pub inserted: u64,
    /// Points the decimation removed after.
    pub removed: usize,
}

/// The mesh of greedy insertion from `start` (grid indices; the corners are added) to E_max ≤
/// `bound`, decimated while E_max stays ≤ `bound`. Refuses a bound that is negative, NaN or
/// infinite and indices off the grid.
pub fn mesh_within(
    hf: Arc<Heightfield>,
    start: &[u32],
    bound: f64,
) -> Result<MaxErrorMesh, ParamsError> {
    made_within(hf, start, bound, false)
}

/// [`mesh_within`] on a tile: the decimation keeps every vertex on the tile's border, which its
/// neighbours share (insertion may still add border points: the caller checks for them).
#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn tile_mesh_within(
    hf: Arc<Heightfield>,
    start: &[u32],
    bound: f64,
) -> Result<MaxErrorMesh, ParamsError> {
    made_within(hf, start, bound, true)
}

fn made_within(
    hf: Arc<Heightfield>,
    start: &[u32],
    bound: f64,
    keep_border: bool,
) -> Result<MaxErrorMesh, ParamsError> {
    let params = GreedyParams {
        rule: InsertionRule::MaxError,
        stop: GreedyStop::MaxError(bound),
        // Only the final meshes: the sweep's recordings would cost a pass over the mesh each.
        records: 2,
        decimate: true,
        ..GreedyParams::default()
    };
    let mut run = GreedyInsertion::from_kept(hf, params, start)?;
    if keep_border {
        run.keep_border_in_decimation();
    }
    run.run_to_end();
    let score = run
        .recorded()
        .last()
        .expect("a finished run records its final mesh")
        .score;
    Ok(MaxErrorMesh {
        kept: run.kept(),
        score,
        inserted: run.progress().evaluations,
        removed: run.removed(),
    })
}
