//! 3D Tiles 1.1 as terrain, in the layout CesiumJS's `Cesium3DTilesTerrainProvider` reads: the
//! geographic two-root quadtree as two implicit tilesets (the root's two children, one per
//! hemisphere), binary subtree files with tile and content availability and a tile metadata
//! table (minimum and maximum height, bounding sphere, horizon occlusion point, by their 3D
//! Tiles semantics), and one `.glb` per tile: positions in a y-up frame placed by the node's
//! matrix, and the `CESIUM_tile_edges` lists of west, south, east and north edge vertices.

use super::scheme::TileId;
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};

/// Levels per subtree file.
pub const SUBTREE_LEVELS: u32 = 6;

/// What a tile's subtree row says about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileInfo {
    /// The lowest and highest heights over the ellipsoid in the tile.
    pub min_height: f64,
    pub max_height: f64,
    /// A sphere holding every vertex (ECEF): centre and radius.
    pub sphere: [f64; 4],
    /// The horizon occlusion point, in the ellipsoid-scaled frame.
    pub horizon_occlusion: [f64; 3],
}

/// A tile's place in its hemisphere's implicit tileset: root (0 west, 1 east), level, x and y
/// (y from the south, as the TMS rows).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Implicit {
    pub root: u64,
    pub level: u32,
    pub x: u64,
    pub y: u64,
}

impl Implicit {
    /// The implicit coordinates of geographic TMS tile `id`.
    pub fn of(id: TileId) -> Self {
        let across = 1u64 << id.zoom;
        Implicit {
            root: id.x / across,
            level: id.zoom,
            x: id.x % across,
            y: id.y,
        }
    }
}

/// The path of a tile's glb, as the content URI template names it.
pub fn glb_path(id: TileId) -> String {
    let t = Implicit::of(id);
    format!("{}/{}/{}/{}.glb", t.root, t.level, t.x, t.y)
}

/// The path of the subtree file whose root is `t`.
pub fn subtree_path(t: Implicit) -> String {
    format!("{}/subtrees/{}/{}/{}.subtree", t.root, t.level, t.x, t.y)
}

/// Interleaves `x` (even bits) and `y` (odd bits): the quadtree's Morton index.
pub fn morton(x: u64, y: u64) -> u64 {
    let mut m = 0;
    for b in 0..32 {
        m |= ((x >> b) & 1) << (2 * b) | ((y >> b) & 1) << (2 * b + 1);
    }
    m
}

fn pad_to_8(bytes: &mut Vec<u8>, fill: u8) {
    while !bytes.len().is_multiple_of(8) {
        bytes.push(fill);
    }
}

/// A binary buffer of 8-byte-aligned views.
#[derive(Default)]
struct Views {
    bin: Vec<u8>,
    views: Vec<Value>,
}

impl Views {
    fn add(&mut self, bytes: &[u8]) -> usize {
        pad_to_8(&mut self.bin, 0);
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }
}

fn bits(set: &[usize], count: usize) -> Vec<u8> {
    let mut out = vec![0u8; count.div_ceil(8)];
    for &i in set {
        out[i / 8] |= 1 << (i % 8);
    }
    out
}

/// The subtree file rooted at `top`: availability of its `levels` levels from `info` (every
/// available tile has content), its tiles' metadata rows in availability order, and which
/// child subtrees (roots at `top.level + levels`) are in `info`.
pub fn subtree(top: Implicit, levels: u32, info: &BTreeMap<Implicit, TileInfo>) -> Vec<u8> {
    let mut available: Vec<(usize, TileInfo)> = Vec::new();
    for l in 0..levels {
        let offset = ((1usize << (2 * l)) - 1) / 3;
        for x in 0..1u64 << l {
            for y in 0..1u64 << l {
                let t = Implicit {
                    root: top.root,
                    level: top.level + l,
                    x: (top.x << l) + x,
                    y: (top.y << l) + y,
                };
                if let Some(i) = info.get(&t) {
                    available.push((offset + morton(x, y) as usize, *i));
                }
            }
        }
    }
    available.sort_by_key(|a| a.0);
    let tile_bits = ((1usize << (2 * levels)) - 1) / 3;
    let index: Vec<usize> = available.iter().map(|a| a.0).collect();
    let mut children = Vec::new();
    for x in 0..1u64 << levels {
        for y in 0..1u64 << levels {
            let t = Implicit {
                root: top.root,
                level: top.level + levels,
                x: (top.x << levels) + x,
                y: (top.y << levels) + y,
            };
            if info.contains_key(&t) {
                children.push(morton(x, y) as usize);
            }
        }
    }
    let mut v = Views::default();
    let tiles = v.add(&bits(&index, tile_bits));
    let child_availability = if children.is_empty() {
        json!({"constant": 0})
    } else {
        let view = v.add(&bits(&children, 1 << (2 * levels)));
        json!({"bitstream": view, "availableCount": children.len()})
    };
    let column = |f: &dyn Fn(&TileInfo) -> Vec<f64>| -> Vec<u8> {
        available
            .iter()
            .flat_map(|(_, i)| f(i))
            .flat_map(f64::to_le_bytes)
            .collect()
    };
    let min = v.add(&column(&|i| vec![i.min_height]));
    let max = v.add(&column(&|i| vec![i.max_height]));
    let sphere = v.add(&column(&|i| i.sphere.to_vec()));
    let horizon = v.add(&column(&|i| i.horizon_occlusion.to_vec()));
    pad_to_8(&mut v.bin, 0);
    let doc = json!({
        "buffers": [{"byteLength": v.bin.len()}],
        "bufferViews": v.views,
        "tileAvailability": {"bitstream": tiles, "availableCount": available.len()},
        "contentAvailability": [{"bitstream": tiles, "availableCount": available.len()}],
        "childSubtreeAvailability": child_availability,
        "propertyTables": [{
            "class": "tile",
            "count": available.len(),
            "properties": {
                "minimumHeight": {"values": min},
                "maximumHeight": {"values": max},
                "boundingSphere": {"values": sphere},
                "horizonOcclusionPoint": {"values": horizon},
            },
        }],
        "tileMetadata": 0,
    });
    let mut text = serde_json::to_vec(&doc).expect("JSON serialises");
    pad_to_8(&mut text, b' ');
    let mut out = Vec::with_capacity(24 + text.len() + v.bin.len());
    out.extend_from_slice(b"subt");
    out.extend_from_slice(&1u32.to_le_bytes());
    out.extend_from_slice(&(text.len() as u64).to_le_bytes());
    out.extend_from_slice(&(v.bin.len() as u64).to_le_bytes());
    out.extend_from_slice(&text);
    out.extend_from_slice(&v.bin);
    out
}

/// The metadata schema whose semantics the terrain provider reads.
pub fn schema() -> Value {
    let scalar = |semantic: &str| json!({"type": "SCALAR", "componentType": "FLOAT64", "semantic": semantic});
    json!({
        "id": "paretomesh_terrain",
        "classes": {"tile": {"properties": {
            "minimumHeight": scalar("TILE_MINIMUM_HEIGHT"),
            "maximumHeight": scalar("TILE_MAXIMUM_HEIGHT"),
            "boundingSphere": {"type": "SCALAR", "componentType": "FLOAT64", "array": true, "count": 4, "semantic": "TILE_BOUNDING_SPHERE"},
            "horizonOcclusionPoint": {"type": "VEC3", "componentType": "FLOAT64", "semantic": "TILE_HORIZON_OCCLUSION_POINT"},
        }}},
    })
}

/// Every file besides the glbs: tileset.json (with `extras` under its `paretomesh` key) and the
/// subtree files of both hemispheres, from every tile's row.
pub fn tileset_files(
    info: &BTreeMap<Implicit, TileInfo>,
    geometric_error: f64,
    extras: Value,
) -> Vec<(String, Vec<u8>)> {
    let available_levels = info.keys().map(|t| t.level + 1).max().unwrap_or(1);
    let levels = SUBTREE_LEVELS.min(available_levels);
    let lo = info
        .values()
        .map(|i| i.min_height)
        .fold(f64::INFINITY, f64::min);
    let hi = info
        .values()
        .map(|i| i.max_height)
        .fold(f64::NEG_INFINITY, f64::max);
    let pi = std::f64::consts::PI;
    let tops: BTreeSet<Implicit> = info
        .keys()
        .filter(|t| t.level.is_multiple_of(levels))
        .copied()
        .collect();
    let mut files: Vec<(String, Vec<u8>)> = tops
        .iter()
        .map(|&t| (subtree_path(t), subtree(t, levels, info)))
        .collect();
    let child = |root: u64| {
        let west = -pi + root as f64 * pi;
        json!({
            "boundingVolume": {"region": [west, -pi / 2.0, west + pi, pi / 2.0, lo, hi]},
            "geometricError": geometric_error,
            "refine": "REPLACE",
            "content": {"uri": format!("{root}/{{level}}/{{x}}/{{y}}.glb")},
            "implicitTiling": {
                "subdivisionScheme": "QUADTREE",
                "subtreeLevels": levels,
                "availableLevels": available_levels,
                "subtrees": {"uri": format!("{root}/subtrees/{{level}}/{{x}}/{{y}}.subtree")},
            },
        })
    };
    let tileset = json!({
        "asset": {"version": "1.1", "generator": "ParetoMesh"},
        "schema": schema(),
        "geometricError": geometric_error,
        "root": {
            "boundingVolume": {"region": [-pi, -pi / 2.0, pi, pi / 2.0, lo, hi]},
            "geometricError": geometric_error,
            "refine": "REPLACE",
            "children": [child(0), child(1)],
        },
        "extras": {"paretomesh": extras},
    });
    files.insert(
        0,
        (
            "tileset.json".into(),
            serde_json::to_vec_pretty(&tileset).expect("JSON serialises"),
        ),
    );
    files
}

/// A tile's glb: `positions` (ECEF) placed by the node's matrix about `center` in glTF's y-up
/// frame (CesiumJS turns it z-up), `triangles` counter-clockwise seen from above, and the
/// west, south, east and north `edges` as `CESIUM_tile_edges` accessors.
pub fn glb(
    center: [f64; 3],
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    edges: &[Vec<u32>; 4],
) -> Vec<u8> {
    // y-up about the centre: (x, y, z) ECEF is (x, -z, y) of the node's frame.
    let local: Vec<[f32; 3]> = positions
        .iter()
        .map(|p| {
            [
                (p[0] - center[0]) as f32,
                (p[2] - center[2]) as f32,
                (center[1] - p[1]) as f32,
            ]
        })
        .collect();
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in &local {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let mut v = Views::default();
    let u32s = |list: &mut dyn Iterator<Item = u32>| -> Vec<u8> {
        list.flat_map(u32::to_le_bytes).collect()
    };
    let position_bytes: Vec<u8> = local
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    let pos_view = v.add(&position_bytes);
    let index_view = v.add(&u32s(&mut triangles.iter().flatten().copied()));
    let edge_views: Vec<usize> = edges
        .iter()
        .map(|e| v.add(&u32s(&mut e.iter().copied())))
        .collect();
    pad_to_8(&mut v.bin, 0);
    let mut views = v.views.clone();
    views[pos_view]["target"] = json!(34962);
    views[index_view]["target"] = json!(34963);
    let mut accessors = vec![
        json!({"bufferView": pos_view, "componentType": 5126, "count": local.len(), "type": "VEC3", "min": lo, "max": hi}),
        json!({"bufferView": index_view, "componentType": 5125, "count": triangles.len() * 3, "type": "SCALAR"}),
    ];
    for (view, e) in edge_views.iter().zip(edges) {
        accessors.push(
            json!({"bufferView": view, "componentType": 5125, "count": e.len(), "type": "SCALAR"}),
        );
    }
    let matrix = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, center[0], center[2],
        -center[1], 1.0,
    ];
    let doc = json!({
        "asset": {"version": "2.0", "generator": "ParetoMesh"},
        "extensionsUsed": ["CESIUM_tile_edges"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "matrix": matrix}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0},
            "indices": 1,
            "mode": 4,
            "extensions": {"CESIUM_tile_edges": {"left": 2, "bottom": 3, "right": 4, "top": 5}},
        }]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": v.bin.len()}],
    });
    let mut text = serde_json::to_vec(&doc).expect("JSON serialises");
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let mut out = Vec::with_capacity(28 + text.len() + v.bin.len());
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((28 + text.len() + v.bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&(v.bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&v.bin);
    out
}
