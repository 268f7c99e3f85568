//! The mesh of a tiled front's member: the union of its tiles' canonical triangulations.

use super::TilingError;
use super::assemble::TiledFront;
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
        Ok(TiledMesh { kept, triangles })
    }
}
