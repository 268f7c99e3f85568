//! The shown mesh as binary glTF (`.glb`, see [`crate::export::write_glb`]) for the app's export
//! button: positions in the input's own coordinates, smooth normals and, when the error map is
//! shown, vertex colours that carry it.

use super::geometry::error_colour;
use super::state::ShownMesh;
use crate::evaluator::exact::predicates::Lattice;
use crate::evaluator::raster::Grid;
use crate::export::WorldMesh;
use crate::export::{GlbMesh, VertexColors, vertex_normals, write_glb};
use crate::heightfield::Heightfield;

/// The error map at the mesh's vertices: a kept point interpolates itself exactly, so a vertex
/// carries the mean |z − z̃| of the grid points its triangles own (the error of the area it
/// spans), coloured with the view's ramp on the view's scale (0 to the largest point error,
/// as the legend says).
pub(crate) fn vertex_error_colours(hf: &Heightfield, mesh: &ShownMesh) -> Vec<[u8; 4]> {
    let grid = Grid {
        width: hf.width() as i64,
        height: hf.height() as i64,
        z: hf.z(),
    };
    let lattice = Lattice::new(hf.width());
    // Per vertex (in `mesh.kept` order): error summed over the owned points of its triangles,
    // and how many points that is (a point owned by a triangle counts for each of its corners).
    let mut sum = vec![0.0; mesh.kept.len()];
    let mut count = vec![0usize; mesh.kept.len()];
    for tri in &mesh.triangles {
        let (mut e, mut n) = (0.0, 0usize);
        grid.for_each_point(tri.map(|i| lattice.point(i)), |i, _| {
            e += mesh.point_error[i];
            n += 1;
        });
        for g in tri {
            if let Ok(k) = mesh.kept.binary_search(g) {
                sum[k] += e;
                count[k] += n;
            }
        }
    }
    let max_error = mesh.point_error.iter().cloned().fold(0.0, f64::max);
    let scale = if max_error > 0.0 {
        1.0 / max_error
    } else {
        0.0
    };
    sum.iter()
        .zip(&count)
        .map(|(&e, &n)| {
            let mean = if n > 0 { e / n as f64 } else { 0.0 };
            error_colour(mean * scale).map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
        })
        .collect()
}

/// `mesh` on `hf` as a `.glb` file; with `error_map`, its vertex colours carry the error map
/// (see [`vertex_error_colours`]). Fails with a message when the mesh is inconsistent.
pub(crate) fn mesh_glb(
    hf: &Heightfield,
    mesh: &ShownMesh,
    error_map: bool,
) -> Result<Vec<u8>, String> {
    let world = WorldMesh::new(hf, &mesh.kept, &mesh.triangles)?;
    let indices: Vec<u32> = world.triangles.iter().flatten().copied().collect();
    let normals = vertex_normals(&world.vertices, &indices);
    let colours = error_map.then(|| vertex_error_colours(hf, mesh));
    write_glb(&GlbMesh {
        positions: &world.vertices,
        normals: &normals,
        indices: &indices,
        colors: colours.as_deref().map(VertexColors::Rgba),
    })
    .map_err(|e| e.to_string())
}
