//! A triangle mesh as read from PLY, OBJ or STL, and the limits every mesh parser checks.

use super::error::ImportError;

/// Most vertices a mesh file may claim (16 M): checked against the header before allocating.
pub(super) const MAX_VERTICES: usize = 1 << 24;
/// Most triangles a mesh file may claim (32 M, twice [`MAX_VERTICES`] as in a closed surface).
pub(super) const MAX_TRIANGLES: usize = 1 << 25;
/// Largest side of an automatically chosen resampling grid (257×257 ≈ 66 k points).
pub(super) const DEFAULT_MAX_SIDE: usize = 257;

/// Vertices in 3-D and triangles as vertex-index triples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles; every index is `< vertices.len()`.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Checks what every parser promises: within the limits, at least one vertex, only finite
    /// coordinates, only valid indices. `format` names the file format in the error.
    pub fn validate(&self, format: &'static str) -> Result<(), ImportError> {
        check_counts(
            format,
            self.vertices.len() as u64,
            self.triangles.len() as u64,
        )?;
        if self.vertices.is_empty() {
            return Err(ImportError::EmptyMesh { format });
        }
        if let Some(i) = self
            .vertices
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(ImportError::NotFinite {
                format,
                message: format!("vertex {i} is {:?}", self.vertices[i]),
            });
        }
        let n = self.vertices.len();
        if let Some(t) = self
            .triangles
            .iter()
            .position(|t| t.iter().any(|&i| i as usize >= n))
        {
            return Err(ImportError::Malformed {
                format,
                message: format!(
                    "triangle {t} uses vertex {:?}, but there are only {n} vertices",
                    self.triangles[t]
                ),
            });
        }
        Ok(())
    }
}

/// Checks claimed vertex and triangle counts against [`MAX_VERTICES`] and [`MAX_TRIANGLES`].
pub(super) fn check_counts(
    format: &'static str,
    vertices: u64,
    triangles: u64,
) -> Result<(), ImportError> {
    if vertices > MAX_VERTICES as u64 {
        return Err(ImportError::OverLimit {
            format,
            what: "vertices",
            claimed: vertices,
            limit: MAX_VERTICES as u64,
        });
    }
    if triangles > MAX_TRIANGLES as u64 {
        return Err(ImportError::OverLimit {
            format,
            what: "triangles",
            claimed: triangles,
            limit: MAX_TRIANGLES as u64,
        });
    }
    Ok(())
}
