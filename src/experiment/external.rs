//! Fronts made by other tools, re-scored with the project's evaluator so that they can stand in
//! the same tables as the project's methods.
//!
//! Inputs (read from bytes here; the command line finds the files):
//! - a front.json ([`FrontFile`]): every member, its kept grid indices and, when listed, triangles;
//! - a JSON list of meshes `[{"vertices": [grid indices], "triangles": [[a, b, c], …]}, …]`, the
//!   triangles indexing `vertices` (0-based); without `triangles` the mesh is the project's
//!   Delaunay triangulation of its vertices, which must include the four grid corners;
//! - a PLY or OBJ mesh whose vertices lie on grid points: x = column, y = row in grid units, each
//!   within `GRID_TOLERANCE` of a whole number inside the grid. z is ignored: the error is
//!   measured against the grid's own heights.
//!
//! A mesh is scored on its own triangles ([`Evaluator::score_triangulation`]), so a mesh that
//! is not Delaunay is measured as the tool made it; its triangles must cover the grid rectangle
//! exactly once, edge to edge. Its kept set is the grid points its triangles use. Meshes that
//! are not Delaunay triangulations of their points are counted, since the project's own methods
//! are always scored on a Delaunay triangulation. A mesh that fails any check is refused with
//! the reason and the rest are kept.

use super::results::{ExternalFront, RejectedMesh};
use crate::evaluator::{Evaluator, is_delaunay};
use crate::front::{Front, Solution};
use crate::front_file::FrontFile;
use crate::import::{TriangleMesh, obj, ply};
use serde::Deserialize;

/// How far (in grid units) a PLY or OBJ vertex may lie from its grid point: far below a grid
/// step, far above the rounding of coordinates written with a few decimals.
pub(crate) const GRID_TOLERANCE: f64 = 1e-3;

/// One mesh over grid points, before it is scored.
#[derive(Clone, Debug, PartialEq)]
pub struct GridMesh {
    /// Its vertices as grid indices (y·W + x).
    pub vertices: Vec<u64>,
    /// Its triangles as grid indices, or `None` for the project's Delaunay triangulation of
    /// `vertices`.
    pub triangles: Option<Vec<[u64; 3]>>,
}

/// A mesh read from an outside file, or the reason it could not be read, with a label that
/// says which mesh it is.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshInput {
    /// A file name or a position in the file.
    pub label: String,
    /// The mesh, or why it is unusable.
    pub mesh: Result<GridMesh, String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ListedMesh {
    vertices: Vec<u64>,
    #[serde(default)]
    triangles: Option<Vec<[u64; 3]>>,
}

/// The meshes of a JSON file: a front.json (an object with `front`) or a list of meshes.
///
/// Errors (the whole file): not JSON, neither form, or a front.json made on another grid size.
/// A malformed entry of a list is one refused mesh, not an error.
pub fn from_json(bytes: &[u8], width: usize, height: usize) -> Result<Vec<MeshInput>, String> {
    let value: serde_json::Value =
        serde_json::from_slice(bytes).map_err(|e| format!("not JSON: {e}"))?;
    match value {
        serde_json::Value::Object(ref o) if o.contains_key("front") => {
            let file: FrontFile = serde_json::from_value(value)
                .map_err(|e| format!("not a front.json as `paretomesh run` writes it: {e}"))?;
            if (file.header.grid.width, file.header.grid.height) != (width, height) {
                return Err(format!(
                    "the front.json was made on a {}×{} grid, this data set is {width}×{height}",
                    file.header.grid.width, file.header.grid.height
                ));
            }
            Ok(file
                .front
                .into_iter()
                .enumerate()
                .map(|(k, m)| MeshInput {
                    label: format!("member {k} (T = {})", m.solution.t),
                    mesh: Ok(GridMesh {
                        vertices: m.solution.kept.iter().map(|&i| i.into()).collect(),
                        triangles: m
                            .triangles
                            .map(|tris| tris.iter().map(|t| t.map(u64::from)).collect()),
                    }),
                })
                .collect())
        }
        serde_json::Value::Array(entries) => Ok(entries
            .into_iter()
            .enumerate()
            .map(|(k, entry)| MeshInput {
                label: format!("mesh {k}"),
                mesh: serde_json::from_value::<ListedMesh>(entry)
                    .map_err(|e| format!("not a mesh {{vertices, triangles}}: {e}"))
                    .and_then(listed_mesh),
            })
            .collect()),
        _ => Err(
            "expected a front.json (an object with \"front\") or a list of meshes [{\"vertices\": […], \"triangles\": […]}, …]"
                .to_string(),
        ),
    }
}

/// A listed mesh's triangles, from positions in its vertex list to grid indices.
fn listed_mesh(m: ListedMesh) -> Result<GridMesh, String> {
    let triangles = match m.triangles {
        None => None,
        Some(tris) => Some(
            tris.iter()
                .map(|t| {
                    let mut out = [0; 3];
                    for (o, &v) in out.iter_mut().zip(t) {
                        *o = *m.vertices.get(v as usize).ok_or_else(|| {
                            format!(
                                "triangle {t:?} uses vertex {v}, but the mesh has {} vertices",
                                m.vertices.len()
                            )
                        })?;
                    }
                    Ok(out)
                })
                .collect::<Result<Vec<_>, String>>()?,
        ),
    };
    Ok(GridMesh {
        vertices: m.vertices,
        triangles,
    })
}

/// One PLY or OBJ mesh file (`extension` says which), its vertices mapped to grid points.
pub fn from_mesh_file(
    label: String,
    extension: &str,
    bytes: &[u8],
    width: usize,
    height: usize,
) -> MeshInput {
    let parsed = match extension.to_ascii_lowercase().as_str() {
        "ply" => ply::parse(bytes).map_err(|e| e.to_string()),
        "obj" => obj::parse(bytes).map_err(|e| e.to_string()),
        other => Err(format!("not a PLY or OBJ file (extension {other:?})")),
    };
    MeshInput {
        label,
        mesh: parsed.and_then(|m| on_grid(&m, width, height)),
    }
}

/// The mesh over grid indices, or the first vertex that is not on a grid point.
fn on_grid(mesh: &TriangleMesh, width: usize, height: usize) -> Result<GridMesh, String> {
    let vertices = mesh
        .vertices
        .iter()
        .enumerate()
        .map(|(i, &[x, y, _])| {
            let (cx, cy) = (x.round(), y.round());
            if (x - cx).abs() > GRID_TOLERANCE || (y - cy).abs() > GRID_TOLERANCE {
                return Err(format!(
                    "vertex {i} at ({x}, {y}) is not on a grid point (x = column, y = row, within {GRID_TOLERANCE})"
                ));
            }
            if cx < 0.0 || cy < 0.0 || cx >= width as f64 || cy >= height as f64 {
                return Err(format!(
                    "vertex {i} at ({x}, {y}) is outside the {width}×{height} grid"
                ));
            }
            Ok(cy as u64 * width as u64 + cx as u64)
        })
        .collect::<Result<Vec<u64>, String>>()?;
    let triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|v| vertices[v as usize]))
        .collect();
    Ok(GridMesh {
        vertices,
        triangles: Some(triangles),
    })
}

/// Scores one mesh: its solution, and whether its triangles are the project's Delaunay
/// triangulation of its points.
fn score(mesh: &GridMesh, evaluator: &mut Evaluator) -> Result<(Solution, bool), String> {
    let hf = evaluator.heightfield().clone();
    let n = hf.len() as u64;
    let grid_index = |i: u64| {
        u32::try_from(i).ok().filter(|_| i < n).ok_or_else(|| {
            format!(
                "grid index {i} is out of range: the {}×{} grid has {n} points",
                hf.width(),
                hf.height()
            )
        })
    };
    match &mesh.triangles {
        Some(tris) => {
            if tris.is_empty() {
                return Err("the mesh has no triangles".to_string());
            }
            let tris = tris
                .iter()
                .map(|t| Ok([grid_index(t[0])?, grid_index(t[1])?, grid_index(t[2])?]))
                .collect::<Result<Vec<[u32; 3]>, String>>()?;
            let s = evaluator
                .score_triangulation(&tris)
                .map_err(|e| e.to_string())?;
            let mut kept: Vec<u32> = tris.iter().flatten().copied().collect();
            kept.sort_unstable();
            kept.dedup();
            let delaunay = is_delaunay(&tris, hf.width());
            Ok((solution(s, kept), delaunay))
        }
        None => {
            let mut kept = mesh
                .vertices
                .iter()
                .map(|&i| grid_index(i))
                .collect::<Result<Vec<u32>, String>>()?;
            kept.sort_unstable();
            kept.dedup();
            if let Some(c) = hf
                .corners()
                .into_iter()
                .find(|c| kept.binary_search(c).is_err())
            {
                let (x, y) = hf.coords(c);
                return Err(format!(
                    "the mesh leaves out the grid corner ({x}, {y}); a mesh without triangles must keep all four"
                ));
            }
            let s = evaluator.score(&kept).map_err(|e| e.to_string())?;
            Ok((solution(s, kept), true))
        }
    }
}

fn solution(s: crate::evaluator::Score, kept: Vec<u32>) -> Solution {
    Solution { score: s, kept }
}

/// Scores every mesh of one outside front on `evaluator`'s grid and keeps the valid ones:
/// the front is their non-dominated set; every refused mesh is listed with its reason.
pub fn rescore(
    name: &str,
    source: &str,
    inputs: Vec<MeshInput>,
    evaluator: &mut Evaluator,
) -> ExternalFront {
    let meshes = inputs.len();
    let mut rejected = Vec::new();
    let mut valid = Vec::new();
    let mut not_delaunay = 0;
    for input in inputs {
        match input.mesh.and_then(|m| score(&m, evaluator)) {
            Ok((s, delaunay)) => {
                not_delaunay += usize::from(!delaunay);
                valid.push(s);
            }
            Err(reason) => rejected.push(RejectedMesh {
                mesh: input.label,
                reason,
            }),
        }
    }
    ExternalFront {
        name: name.to_string(),
        source: source.to_string(),
        meshes,
        rejected,
        not_delaunay,
        front: Front::merged(&valid).solutions().to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Heightfield;
    use std::sync::Arc;

    /// A 3×3 grid with a bump in the middle (index 4).
    fn evaluator() -> Evaluator {
        let z = vec![0.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 0.0];
        Evaluator::new(Arc::new(Heightfield::new(3, 3, z).unwrap()))
    }

    #[test]
    fn listed_meshes_are_scored_on_their_own_triangles() {
        // Corners only, two triangles over the diagonal 0–8: the bump is missed by 4.
        let json = br#"[{"vertices":[0,2,6,8],"triangles":[[0,1,3],[0,3,2]]},
                        {"vertices":[0,2,6,8,4]},
                        {"vertices":[0,2,6]},
                        {"vertices":[0,2,6,8],"triangles":[[0,1,7]]},
                        {"vertices":[0,2,6,8],"triangles":[[0,1,3]]}]"#;
        let inputs = from_json(json, 3, 3).unwrap();
        let mut ev = evaluator();
        let x = rescore("tool", "list.json", inputs, &mut ev);
        assert_eq!((x.meshes, x.valid(), x.rejected.len()), (5, 2, 3));
        assert!(x.rejected[0].reason.contains("grid corner (2, 2)"), "{x:?}");
        assert!(x.rejected[1].reason.contains("uses vertex 7"), "{x:?}");
        assert!(x.rejected[2].reason.contains("hole"), "{x:?}");
        // (4, 2) and (0, 4): neither dominates the other.
        let points: Vec<_> = x.front.iter().map(|s| (s.e_sum, s.t)).collect();
        assert_eq!(points, vec![(4.0, 2), (0.0, 4)]);
        assert_eq!(x.front[1].kept, vec![0, 2, 4, 6, 8]);
    }

    #[test]
    fn a_mesh_file_must_lie_on_grid_points() {
        let ply = |v: &str| {
            format!(
                "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n{v}\n2 2 0\n3 0 1 3\n3 0 3 2\n"
            )
        };
        let good = from_mesh_file("a.ply".into(), "ply", ply("0 2 7").as_bytes(), 3, 3);
        assert_eq!(
            good.mesh.as_ref().unwrap().triangles,
            Some(vec![[0, 2, 8], [0, 8, 6]])
        );
        let off = from_mesh_file("b.ply".into(), "PLY", ply("0.5 2 0").as_bytes(), 3, 3);
        assert!(off.mesh.unwrap_err().contains("not on a grid point"));
        let outside = from_mesh_file("c.ply".into(), "ply", ply("0 3 0").as_bytes(), 3, 3);
        assert!(outside.mesh.unwrap_err().contains("outside the 3×3 grid"));
        let mut ev = evaluator();
        let x = rescore("tool", "dir", vec![good], &mut ev);
        assert_eq!((x.valid(), x.not_delaunay), (1, 0));
        assert_eq!(x.front[0].e_sum, 4.0);
    }

    #[test]
    fn non_delaunay_triangles_are_counted_and_scored_as_given() {
        // Kept: the corners and (1, 0). Delaunay fans out from (1, 0); the diagonal from
        // (0, 0) to (2, 2) instead is a valid cover but not Delaunay.
        let json = br#"[{"vertices":[0,1,2,6,8],"triangles":[[0,1,4],[0,4,3],[1,2,4]]}]"#;
        let mut ev = evaluator();
        let x = rescore(
            "diagonal",
            "d.json",
            from_json(json, 3, 3).unwrap(),
            &mut ev,
        );
        assert_eq!((x.valid(), x.not_delaunay), (1, 1), "{x:?}");
        assert_eq!((x.front[0].e_sum, x.front[0].t), (4.0, 3));
    }

    #[test]
    fn a_front_json_of_another_grid_is_refused_whole() {
        let json = br#"{"grid":{"width":5,"height":5,"source":""},"algorithm":"greedy","params":null,"seed":0,"evaluations":0,"millis":0,"front":[]}"#;
        let err = from_json(json, 3, 3).unwrap_err();
        assert!(err.contains("5×5 grid, this data set is 3×3"), "{err}");
        let err = from_json(b"{\"a\":1}", 3, 3).unwrap_err();
        assert!(
            err.starts_with("expected a front.json (an object with \"front\") or a list"),
            "{err}"
        );
    }
}
