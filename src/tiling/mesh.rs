//! The mesh of a tiled front's member: the union of its tiles' canonical triangulations.
//!
//! A member's mesh is rebuilt in two steps: [`TiledFront::parts`] names each tile's kept set
//! (cheap: a few lists of indices), and [`mesh_of_parts`] triangulates them on the grid (the
//! costly step: every grid point is visited). The browser does the second step in a Web Worker
//! that holds the grid, so the page only hands it the parts.

use super::TilingError;
use super::assemble::TiledFront;
use super::border::TileBorders;
use super::plan::TilePlan;
use super::tile_front::unowned_error;
use crate::evaluator::Evaluator;
use crate::heightfield::Heightfield;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A whole-grid mesh: kept grid indices (increasing) and triangles (whole-grid index triples,
/// counter-clockwise in (x, y), as the evaluator gives them).
#[derive(Clone, Debug, PartialEq)]
pub struct TiledMesh {
    /// Kept grid indices, increasing, without repeats.
    pub kept: Vec<u32>,
    /// Triangles over whole-grid indices.
    pub triangles: Vec<[u32; 3]>,
    /// E_sum scored again from the tiles' meshes (their E shares added in tile order): the
    /// member's recorded E_sum when the grid is the one the front was made on.
    pub e_sum: f64,
    /// E_max scored again.
    pub e_max: f64,
}

/// One tile's share of a whole-grid member: what triangulating it needs besides the tile's
/// heights.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct TilePart {
    /// The tile's index in the plan.
    pub tile: usize,
    /// The member's border level.
    pub level: u8,
    /// The tile's border lines (which of their errors the tile's neighbours count).
    pub borders: TileBorders,
    /// The tile-local kept set, increasing, corners left out (see `TileFront::kept`).
    pub kept: Vec<u32>,
}

impl TiledFront {
    /// The tile parts of member `member`: each tile's chosen candidate as a kept set.
    pub(crate) fn parts(&self, member: usize) -> Result<Vec<TilePart>, TilingError> {
        let m = self.members.get(member).ok_or(TilingError::NoSuchMember {
            member,
            members: self.members.len(),
        })?;
        self.tiles
            .iter()
            .zip(&m.choice)
            .map(|(tile_front, &c)| {
                let candidate =
                    tile_front
                        .candidates
                        .get(c as usize)
                        .ok_or(TilingError::NoSuchMember {
                            member: c as usize,
                            members: tile_front.candidates.len(),
                        })?;
                Ok(TilePart {
                    tile: tile_front.index,
                    level: candidate.level,
                    borders: tile_front.borders.clone(),
                    kept: tile_front.kept(candidate),
                })
            })
            .collect()
    }

    /// The mesh of member `member` on the whole grid `hf`: each tile's chosen candidate
    /// triangulated on the tile (the canonical Delaunay triangulation of its kept points) and
    /// mapped to whole-grid indices.
    pub fn mesh(&self, hf: &Heightfield, member: usize) -> Result<TiledMesh, TilingError> {
        mesh_of_parts(&self.plan, hf, &self.parts(member)?)
    }
}

/// The whole-grid mesh of `parts` (one per tile of `plan`, in tile order) on the grid `hf`.
/// A pure function of its inputs: the same parts give the same bits on any thread.
pub(crate) fn mesh_of_parts(
    plan: &TilePlan,
    hf: &Heightfield,
    parts: &[TilePart],
) -> Result<TiledMesh, TilingError> {
    plan.check_grid(hf)?;
    let given: Vec<usize> = parts.iter().map(|p| p.tile).collect();
    if given != (0..plan.len()).collect::<Vec<_>>() {
        return Err(TilingError::WrongTiles {
            expected: plan.len(),
            given,
        });
    }
    let mut kept = Vec::new();
    let mut triangles = Vec::new();
    let (mut e_sum, mut e_max) = (0.0, 0.0f64);
    for part in parts {
        let tile = plan.tile(part.tile).expect("tile indices were checked");
        if (part.borders.w, part.borders.h) != (tile.w, tile.h) {
            return Err(TilingError::GridMismatch {
                plan: (tile.w, tile.h),
                grid: (part.borders.w, part.borders.h),
            });
        }
        let tile_hf = Arc::new(plan.cut(hf, tile.index)?);
        let mut evaluator = Evaluator::new(tile_hf.clone());
        let evaluation = evaluator
            .evaluate(&part.kept)
            .map_err(|e| TilingError::Evaluate(e.to_string()))?;
        e_sum += evaluation.score.e_sum
            - unowned_error(
                plan,
                tile.index,
                &part.borders,
                tile_hf.z(),
                part.level as usize,
            );
        e_max = e_max.max(evaluation.score.e_max);
        let to_grid = |i: u32| tile.to_grid(i, hf.width());
        kept.extend(
            part.kept
                .iter()
                .chain(tile_hf.corners().iter())
                .map(|&i| to_grid(i)),
        );
        triangles.extend(evaluation.triangles.iter().map(|t| t.map(to_grid)));
    }
    kept.sort_unstable();
    kept.dedup();
    Ok(TiledMesh {
        kept,
        triangles,
        e_sum,
        e_max,
    })
}
