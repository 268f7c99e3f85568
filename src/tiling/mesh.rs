//! The mesh of a tiled front's member: the union of its tiles' canonical triangulations.

use super::TilingError;
use super::assemble::TiledFront;
use super::tile_front::unowned_error;
use crate::evaluator::Evaluator;
use crate::heightfield::Heightfield;
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

impl TiledFront {
    /// The mesh of member `member` on the whole grid `hf`: each tile's chosen candidate
    /// triangulated on the tile (the canonical Delaunay triangulation of its kept points) and
    /// mapped to whole-grid indices.
    pub fn mesh(&self, hf: &Heightfield, member: usize) -> Result<TiledMesh, TilingError> {
        self.plan.check_grid(hf)?;
        let m = self.members.get(member).ok_or(TilingError::NoSuchMember {
            member,
            members: self.members.len(),
        })?;
        let mut kept = Vec::new();
        let mut triangles = Vec::new();
        let (mut e_sum, mut e_max) = (0.0, 0.0f64);
        for (tile_front, &c) in self.tiles.iter().zip(&m.choice) {
            let tile = self
                .plan
                .tile(tile_front.index)
                .expect("an assembled front's tiles are its plan's");
            let candidate =
                tile_front
                    .candidates
                    .get(c as usize)
                    .ok_or(TilingError::NoSuchMember {
                        member: c as usize,
                        members: tile_front.candidates.len(),
                    })?;
            let tile_hf = Arc::new(self.plan.cut(hf, tile.index)?);
            let mut evaluator = Evaluator::new(tile_hf.clone());
            let local = tile_front.kept(candidate);
            let evaluation = evaluator
                .evaluate(&local)
                .map_err(|e| TilingError::Evaluate(e.to_string()))?;
            let level = candidate.level as usize;
            e_sum += evaluation.score.e_sum
                - unowned_error(
                    &self.plan,
                    tile.index,
                    &tile_front.borders,
                    tile_hf.z(),
                    level,
                );
            e_max = e_max.max(evaluation.score.e_max);
            let to_grid = |i: u32| tile.to_grid(i, hf.width());
            kept.extend(
                local
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
}
