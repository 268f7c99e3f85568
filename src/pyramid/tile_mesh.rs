//! One tile's mesh: the canonical Delaunay triangulation of the member's kept points in the
//! tile (its corners added), scored on the tile's own grid points.
//!
//! A tile's border points are on its convex hull, so the triangulation has an edge between
//! every two consecutive ones; the neighbour across that border has the same points on it, and
//! so the same edges: tiles meet without cracks whatever their interiors.

use super::quadtree::Tile;
use crate::evaluator::{EvaluateError, Evaluator};
use crate::heightfield::{Heightfield, HeightfieldError};
use std::sync::Arc;

/// A tile's mesh in the whole grid's indices.
#[derive(Clone, Debug, PartialEq)]
pub struct TileMesh {
    /// The mesh's vertices: grid indices, increasing.
    pub vertices: Vec<u32>,
    /// Triangles as indices into `vertices`, counter-clockwise in (x, y).
    pub triangles: Vec<[u32; 3]>,
    /// The largest |z − z̃| over the tile's grid points, in the surface's units.
    pub e_max: f64,
}

/// The mesh of `tile` over `kept`: grid indices of `hf` inside the tile (its border included)
/// with the tile's corners, increasing, as [`super::quadtree::Level::share_out`] gives them.
pub fn tile_mesh(hf: &Heightfield, tile: &Tile, kept: &[u32]) -> Result<TileMesh, String> {
    let width = hf.width();
    let (tw, th) = tile.size();
    let (x0, y0) = (tile.columns.0, tile.rows.0);
    let z: Vec<f64> = (0..th)
        .flat_map(|ty| {
            let start = (y0 + ty) * width + x0;
            hf.z()[start..start + tw].iter().copied()
        })
        .collect();
    let window = Heightfield::new(tw, th, z).map_err(|e: HeightfieldError| e.to_string())?;
    let local: Vec<u32> = kept
        .iter()
        .map(|&g| {
            let (x, y) = (g as usize % width, g as usize / width);
            debug_assert!(tile.contains(x, y));
            ((y - y0) * tw + (x - x0)) as u32
        })
        .collect();
    let evaluation = Evaluator::new(Arc::new(window))
        .evaluate(&local)
        .map_err(|e: EvaluateError| e.to_string())?;
    let global = |l: u32| ((y0 + l as usize / tw) * width + x0 + l as usize % tw) as u32;
    // Local indices grow with global ones (same rows, same order within a row), so the
    // sorted local list maps to a sorted global one.
    let mut vertices: Vec<u32> = evaluation.triangles.iter().flatten().copied().collect();
    vertices.sort_unstable();
    vertices.dedup();
    let position = |l: u32| vertices.binary_search(&l).expect("a triangle corner") as u32;
    let triangles = evaluation
        .triangles
        .iter()
        .map(|t| t.map(position))
        .collect();
    Ok(TileMesh {
        vertices: vertices.into_iter().map(global).collect(),
        triangles,
        e_max: evaluation.score.e_max,
    })
}
