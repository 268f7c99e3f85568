//! Wavefront OBJ meshes, read with the `tobj` crate (a maintained loader after tinyobjloader).
//!
//! All objects and groups are merged into one mesh; polygons are split into triangles by tobj;
//! points, lines, normals, texture coordinates and materials are ignored (no `.mtl` is read: the
//! browser has only the one file). Only vertices that some face uses are kept, as tobj does.

use super::error::ImportError;
use super::triangle_mesh::{TriangleMesh, check_counts};

const FORMAT: &str = "OBJ";

/// Parses an OBJ file into a validated mesh. Never panics: every bad input is an
/// [`ImportError`].
pub fn parse(bytes: &[u8]) -> Result<TriangleMesh, ImportError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let mut reader = std::io::BufReader::new(bytes);
    // Materials are not needed for heights; an empty material list for every `mtllib`.
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Ok((Vec::new(), Default::default()))
    })
    .map_err(|e| ImportError::Malformed {
        format: FORMAT,
        message: e.to_string(),
    })?;
    let vertices: usize = models.iter().map(|m| m.mesh.positions.len() / 3).sum();
    let triangles: usize = models.iter().map(|m| m.mesh.indices.len() / 3).sum();
    check_counts(FORMAT, vertices as u64, triangles as u64)?;
    let mut mesh = TriangleMesh {
        vertices: Vec::with_capacity(vertices),
        triangles: Vec::with_capacity(triangles),
    };
    for model in &models {
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(
            model
                .mesh
                .positions
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]]),
        );
        mesh.triangles.extend(
            model
                .mesh
                .indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    if mesh.triangles.is_empty() {
        return Err(ImportError::EmptyMesh { format: FORMAT });
    }
    mesh.validate(FORMAT)?;
    Ok(mesh)
}
