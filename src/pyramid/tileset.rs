//! A pyramid's files: each tile's mesh as binary glTF, and tileset.json (3D Tiles 1.1) that
//! ties them into a quadtree with bounding boxes, geometric errors and REPLACE refinement.

use super::globe::Frame;
use super::quadtree::Tile;
use super::tile_mesh::tile_mesh;
use crate::export::{GlbMesh, vertex_normals, write_glb};
use crate::heightfield::Heightfield;
use serde_json::{Value, json};

/// An axis-aligned box in the tileset's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest x, y, z.
    pub min: [f64; 3],
    /// Largest x, y, z.
    pub max: [f64; 3],
}

impl Bounds {
    fn of(points: &[[f64; 3]]) -> Self {
        let mut b = Self {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        };
        for p in points {
            for (k, &v) in p.iter().enumerate() {
                b.min[k] = b.min[k].min(v);
                b.max[k] = b.max[k].max(v);
            }
        }
        b
    }

    fn union(self, other: Self) -> Self {
        Self {
            min: std::array::from_fn(|k| self.min[k].min(other.min[k])),
            max: std::array::from_fn(|k| self.max[k].max(other.max[k])),
        }
    }

    /// The 3D Tiles `box`: centre and three half-axes. A flat side gets a small thickness,
    /// since a box with a zero half-axis has no volume to test against.
    pub(crate) fn to_box(self) -> [f64; 12] {
        let c: [f64; 3] = std::array::from_fn(|k| (self.min[k] + self.max[k]) / 2.0);
        let half: [f64; 3] = std::array::from_fn(|k| (self.max[k] - self.min[k]) / 2.0);
        let floor = 1e-3 * half.iter().copied().fold(0.0, f64::max);
        let h = half.map(|v| v.max(floor).max(1e-6));
        [
            c[0], c[1], c[2], h[0], 0.0, 0.0, 0.0, h[1], 0.0, 0.0, 0.0, h[2],
        ]
    }
}

/// One written tile: where it is, its glTF bytes, its bounds in the tileset's frame and its
/// own vertical error.
#[derive(Clone, Debug)]
pub struct TileContent {
    /// The tile.
    pub tile: Tile,
    /// Binary glTF of its mesh (y up, as glTF content of 3D Tiles is).
    pub glb: Vec<u8>,
    /// Its vertices' bounding box in the tileset's frame (z up).
    pub bounds: Bounds,
    /// Largest |z − z̃| over its grid points, in the surface's units.
    pub e_max: f64,
    /// Its triangles.
    pub triangles: usize,
}

/// The content file of `tile`, relative to tileset.json.
pub(super) fn content_uri(tile: &Tile) -> String {
    format!("{}/{}/{}.glb", tile.level, tile.x, tile.y)
}

/// Triangulates `tile` over `kept` (see [`tile_mesh`]) and encodes it in `frame`.
pub(super) fn tile_content(
    hf: &Heightfield,
    frame: &Frame,
    tile: &Tile,
    kept: &[u32],
) -> Result<TileContent, String> {
    let mesh = tile_mesh(hf, tile, kept)?;
    let placed: Vec<[f64; 3]> = mesh
        .vertices
        .iter()
        .map(|&g| frame.place(hf.to_world(g, hf.z()[g as usize])))
        .collect();
    // 3D Tiles turns glTF's y-up into its z-up: (x, y, z) is written as (x, z, −y).
    let positions: Vec<[f64; 3]> = placed.iter().map(|p| [p[0], p[2], -p[1]]).collect();
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let normals = vertex_normals(&positions, &indices);
    let glb = write_glb(&GlbMesh {
        positions: &positions,
        normals: &normals,
        indices: &indices,
        colors: None,
    })
    .map_err(|e| format!("tile {}: {e}", content_uri(tile)))?;
    Ok(TileContent {
        tile: *tile,
        glb,
        bounds: Bounds::of(&placed),
        e_max: mesh.e_max,
        triangles: mesh.triangles.len(),
    })
}

/// What tileset.json records about one level: the front member it shows.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LevelNote {
    /// The member's index in front.json.
    pub member: usize,
    /// Its triangles over the whole grid.
    pub t: usize,
    /// Its E_sum over the whole grid (none for a level whose tiles were chosen one by one).
    pub e_sum: Option<f64>,
    /// Its E_max over the whole grid.
    pub e_max: f64,
}

/// tileset.json for `levels` (level 0 first, each level's tiles row by row, as
/// [`super::quadtree::Level::tiles`] lists them). A tile's geometric error is the largest of
/// its own E_max and its children's errors, so errors never grow down the tree; its box holds
/// its own and its children's. `frame` gives the root transform; `z_range` the tileset's
/// error (nothing shown is off by at most the surface's whole height).
pub(super) fn tileset_json(
    levels: &[Vec<TileContent>],
    notes: &[LevelNote],
    frame: &Frame,
    frame_note: &str,
    z_range: (f64, f64),
) -> Value {
    // Bottom up: each level's errors and bounds, folded with the level below.
    let mut below: Option<(Vec<f64>, Vec<Bounds>, Vec<Value>)> = None;
    for (depth, tiles) in levels.iter().enumerate().rev() {
        let side = 1usize << depth;
        let mut errors = Vec::with_capacity(tiles.len());
        let mut bounds = Vec::with_capacity(tiles.len());
        let mut nodes = Vec::with_capacity(tiles.len());
        for content in tiles {
            let (x, y) = (content.tile.x, content.tile.y);
            let mut error = content.e_max;
            let mut bound = content.bounds;
            let mut children = Vec::new();
            if let Some((child_errors, child_bounds, child_nodes)) = &below {
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let i = (2 * y + dy) * (2 * side) + 2 * x + dx;
                    error = error.max(child_errors[i]);
                    bound = bound.union(child_bounds[i]);
                    children.push(child_nodes[i].clone());
                }
            }
            let mut node = json!({
                "boundingVolume": {"box": bound.to_box()},
                "geometricError": error,
                "refine": "REPLACE",
                "content": {"uri": content_uri(&content.tile)},
            });
            if !children.is_empty() {
                node["children"] = Value::Array(children);
            }
            errors.push(error);
            bounds.push(bound);
            nodes.push(node);
        }
        below = Some((errors, bounds, nodes));
    }
    let (errors, _, mut nodes) = below.expect("a pyramid has a level");
    let mut root = nodes.swap_remove(0);
    if let Some(matrix) = frame.transform() {
        root["transform"] = json!(matrix);
    }
    let levels: Vec<Value> = notes
        .iter()
        .enumerate()
        .map(|(level, n)| {
            json!({"level": level, "member": n.member, "T": n.t, "E_sum": n.e_sum, "E_max": n.e_max})
        })
        .collect();
    json!({
        "asset": {"version": "1.1", "generator": "ParetoMesh"},
        "geometricError": errors[0].max(z_range.1 - z_range.0),
        "root": root,
        "extras": {"frame": frame_note, "levels": levels},
    })
}
