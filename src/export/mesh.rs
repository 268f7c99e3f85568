//! A simplified mesh in the input's own coordinates, the form every mesh writer takes.

use crate::heightfield::Heightfield;

/// A simplified mesh in world coordinates: the kept points and the triangles over them.
///
/// Vertices go through [`Heightfield::to_world`], so a planar or cylindrical unwrap maps back
/// to 3-D.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldMesh {
    /// Vertex positions in the input's coordinates, in the order of the kept grid indices.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

impl WorldMesh {
    /// The mesh of `kept` (increasing grid indices that include every triangle corner) and its
    /// grid-index `triangles`. Fails when a triangle uses a point that is not in `kept`.
    pub fn new(hf: &Heightfield, kept: &[u32], triangles: &[[u32; 3]]) -> Result<Self, String> {
        let vertices = kept
            .iter()
            .map(|&i| hf.to_world(i, hf.z()[i as usize]))
            .collect();
        let local = |g: u32| {
            kept.binary_search(&g)
                .map(|k| k as u32)
                .map_err(|_| format!("triangle vertex {g} is not a kept point"))
        };
        let triangles = triangles
            .iter()
            .map(|t| Ok([local(t[0])?, local(t[1])?, local(t[2])?]))
            .collect::<Result<_, String>>()?;
        Ok(Self {
            vertices,
            triangles,
        })
    }
}
