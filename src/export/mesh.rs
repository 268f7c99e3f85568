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

/// The cross product (b − a) × (c − a): the normal of triangle (`a`, `b`, `c`) by the right-hand
/// rule, with twice its area as length.
pub(super) fn area_normal(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}
