//! 3D Tiles 1.1 as terrain, in the layout CesiumJS's `Cesium3DTilesTerrainProvider` reads: the
//! geographic two-root quadtree as two implicit tilesets (the root's two children, one per
//! hemisphere), binary subtree files with tile and content availability and a tile metadata
//! table (minimum and maximum height, bounding sphere, horizon occlusion point, by their 3D
//! Tiles semantics), and one `.glb` per tile: positions in a y-up frame placed by the node's
//! matrix, normals computed across tile borders, the `CESIUM_tile_edges` lists of west, south,
//! east and north edge vertices and, when asked, the water mask as a property texture.

use super::scheme::TileId;
use super::tile_file::WaterMask;
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};

/// Levels per subtree file.
pub(super) const SUBTREE_LEVELS: u32 = 6;

/// What a tile's subtree row says about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TileInfo {
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
pub(super) struct Implicit {
    pub root: u64,
    pub level: u32,
    pub x: u64,
    pub y: u64,
}

impl Implicit {
    /// The implicit coordinates of geographic TMS tile `id`.
    pub(super) fn of(id: TileId) -> Self {
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
pub(super) fn glb_path(id: TileId) -> String {
    let t = Implicit::of(id);
    format!("{}/{}/{}/{}.glb", t.root, t.level, t.x, t.y)
}

/// The path of the subtree file whose root is `t`.
pub(super) fn subtree_path(t: Implicit) -> String {
    format!("{}/subtrees/{}/{}/{}.subtree", t.root, t.level, t.x, t.y)
}

/// Interleaves `x` (even bits) and `y` (odd bits): the quadtree's Morton index.
pub(super) fn morton(x: u64, y: u64) -> u64 {
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
pub(super) fn subtree(top: Implicit, levels: u32, info: &BTreeMap<Implicit, TileInfo>) -> Vec<u8> {
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
pub(super) fn schema() -> Value {
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
pub(super) fn tileset_files(
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

/// What a tile's glb holds, in ECEF and the tile's vertex order.
pub(super) struct GlbMesh<'a> {
    /// Vertex positions.
    pub(super) positions: &'a [[f64; 3]],
    /// Unit vertex normals (one per position).
    pub(super) normals: &'a [[f64; 3]],
    /// Triangles, counter-clockwise seen from above.
    pub(super) triangles: &'a [[u32; 3]],
    /// West, south, east and north edge vertices.
    pub(super) edges: &'a [Vec<u32>; 4],
    /// The water mask (rows from the north, as the `.terrain` extension has them), if any.
    pub(super) water: Option<&'a WaterMask>,
}

/// The water mask as a grey 8-bit PNG: 256 × 256, or 1 × 1 when uniform. Its rows are the
/// `.terrain` mask's rows in the same order, so CesiumJS uploads the same texture from both.
fn water_png(water: &WaterMask) -> Vec<u8> {
    let (side, bytes): (u32, &[u8]) = match water {
        WaterMask::Uniform(b) => (1, std::slice::from_ref(b)),
        WaterMask::Grid(g) => (256, g),
    };
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, side, side);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().expect("writing to memory");
    writer.write_image_data(bytes).expect("writing to memory");
    writer.finish().expect("writing to memory");
    out
}

/// The metadata schema and property texture by which `Cesium3DTilesTerrainProvider` finds a
/// glb's water mask: a class property of semantic `WATERMASK` read from texture 0.
fn water_metadata() -> Value {
    json!({
        "schema": {
            "id": "paretomesh_terrain_tile",
            "classes": {"terrain": {"properties": {
                "waterMask": {"type": "SCALAR", "componentType": "UINT8", "semantic": "WATERMASK"},
            }}},
        },
        "propertyTextures": [{
            "class": "terrain",
            "properties": {"waterMask": {"index": 0, "texCoord": 0, "channels": [0]}},
        }],
    })
}

/// A tile's glb: `mesh`'s positions placed by the node's matrix about `center` in glTF's y-up
/// frame (CesiumJS turns it z-up), its normals turned the same way, its edges as
/// `CESIUM_tile_edges` accessors and its water mask, if any, as an `EXT_structural_metadata`
/// property texture.
pub(super) fn glb(center: [f64; 3], mesh: &GlbMesh) -> Vec<u8> {
    // y-up about the centre: (x, y, z) ECEF is (x, -z, y) of the node's frame.
    let local: Vec<[f32; 3]> = mesh
        .positions
        .iter()
        .map(|p| {
            [
                (p[0] - center[0]) as f32,
                (p[2] - center[2]) as f32,
                (center[1] - p[1]) as f32,
            ]
        })
        .collect();
    let normals: Vec<[f32; 3]> = mesh
        .normals
        .iter()
        .map(|n| {
            let m = [n[0] as f32, n[2] as f32, -n[1] as f32];
            let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            m.map(|c| c / l)
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
    let f32s = |list: &[[f32; 3]]| -> Vec<u8> {
        list.iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect()
    };
    let pos_view = v.add(&f32s(&local));
    let normal_view = v.add(&f32s(&normals));
    let index_view = v.add(&u32s(&mut mesh.triangles.iter().flatten().copied()));
    let edge_views: Vec<usize> = mesh
        .edges
        .iter()
        .map(|e| v.add(&u32s(&mut e.iter().copied())))
        .collect();
    let image_view = mesh.water.map(|w| v.add(&water_png(w)));
    pad_to_8(&mut v.bin, 0);
    let mut views = v.views.clone();
    views[pos_view]["target"] = json!(34962);
    views[normal_view]["target"] = json!(34962);
    views[index_view]["target"] = json!(34963);
    let mut accessors = vec![
        json!({"bufferView": pos_view, "componentType": 5126, "count": local.len(), "type": "VEC3", "min": lo, "max": hi}),
        json!({"bufferView": normal_view, "componentType": 5126, "count": normals.len(), "type": "VEC3"}),
        json!({"bufferView": index_view, "componentType": 5125, "count": mesh.triangles.len() * 3, "type": "SCALAR"}),
    ];
    for (view, e) in edge_views.iter().zip(mesh.edges) {
        accessors.push(
            json!({"bufferView": view, "componentType": 5125, "count": e.len(), "type": "SCALAR"}),
        );
    }
    let matrix = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, center[0], center[2],
        -center[1], 1.0,
    ];
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": "ParetoMesh"},
        "extensionsUsed": ["CESIUM_tile_edges"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "matrix": matrix}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1},
            "indices": 2,
            "mode": 4,
            "extensions": {"CESIUM_tile_edges": {"left": 3, "bottom": 4, "right": 5, "top": 6}},
        }]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": v.bin.len()}],
    });
    if let Some(view) = image_view {
        doc["extensionsUsed"] = json!(["CESIUM_tile_edges", "EXT_structural_metadata"]);
        doc["images"] = json!([{"bufferView": view, "mimeType": "image/png"}]);
        // Nearest: the mask is 0 or 255 per cell, as CesiumJS samples the .terrain one.
        doc["samplers"] = json!([{"magFilter": 9728, "minFilter": 9728}]);
        doc["textures"] = json!([{"source": 0, "sampler": 0}]);
        doc["extensions"] = json!({"EXT_structural_metadata": water_metadata()});
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn row(k: f64) -> TileInfo {
        TileInfo {
            min_height: k,
            max_height: k + 0.5,
            sphere: [k, 2.0 * k, 3.0 * k, 4.0 * k],
            horizon_occlusion: [-k, -2.0 * k, -3.0 * k],
        }
    }

    fn at(level: u32, x: u64, y: u64) -> Implicit {
        Implicit {
            root: 1,
            level,
            x,
            y,
        }
    }

    /// The subtree file's JSON and binary chunks, after checking its header.
    fn chunks(bytes: &[u8]) -> (Value, &[u8]) {
        assert_eq!(&bytes[..4], b"subt");
        assert_eq!(u32::from_le_bytes(bytes[4..8].try_into().unwrap()), 1);
        let json_len = u64::from_le_bytes(bytes[8..16].try_into().unwrap()) as usize;
        let bin_len = u64::from_le_bytes(bytes[16..24].try_into().unwrap()) as usize;
        assert_eq!(json_len % 8, 0, "the JSON chunk is padded to 8 bytes");
        assert_eq!(bin_len % 8, 0);
        assert_eq!(bytes.len(), 24 + json_len + bin_len);
        let json = serde_json::from_slice(&bytes[24..24 + json_len]).unwrap();
        (json, &bytes[24 + json_len..])
    }

    fn view<'a>(json: &Value, bin: &'a [u8], k: &Value) -> &'a [u8] {
        let v = &json["bufferViews"][k.as_u64().unwrap() as usize];
        let off = v["byteOffset"].as_u64().unwrap() as usize;
        assert_eq!(off % 8, 0, "views start on 8 bytes");
        &bin[off..off + v["byteLength"].as_u64().unwrap() as usize]
    }

    fn f64s(bytes: &[u8]) -> Vec<f64> {
        bytes
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    #[test]
    fn morton_interleaves_x_low_and_y_high() {
        assert_eq!(morton(0, 0), 0);
        assert_eq!(morton(1, 0), 1);
        assert_eq!(morton(0, 1), 2);
        assert_eq!(morton(1, 1), 3);
        assert_eq!(morton(2, 0), 4);
        assert_eq!(morton(3, 5), 0b100111);
    }

    #[test]
    fn a_subtree_has_its_tiles_bits_rows_in_bit_order_and_child_subtrees() {
        // Two levels per subtree under (1, 1, 0, 1): the root, children (0, 3) and (1, 2) of
        // level 2, and one tile at level 3 (a child subtree's root); (0, 0, 0) is elsewhere.
        let mut info = BTreeMap::new();
        info.insert(at(1, 0, 1), row(1.0));
        info.insert(at(2, 1, 2), row(2.0));
        info.insert(at(2, 0, 3), row(3.0));
        info.insert(at(3, 3, 4), row(4.0));
        info.insert(at(2, 3, 3), row(9.0)); // outside the subtree
        let bytes = subtree(at(1, 0, 1), 2, &info);
        let (json, bin) = chunks(&bytes);
        // Level 0: bit 0; level 1 starts at bit 1: (1, 2) is local (1, 0), Morton 1, bit 2;
        // (0, 3) is local (0, 1), Morton 2, bit 3.
        let tiles = view(&json, bin, &json["tileAvailability"]["bitstream"]);
        assert_eq!(tiles, &[0b0000_1101]);
        assert_eq!(json["tileAvailability"]["availableCount"], 3);
        assert_eq!(
            json["contentAvailability"][0]["bitstream"],
            json["tileAvailability"]["bitstream"]
        );
        // Child subtrees at level 3, local (3 − 0·4, 4 − 1·4) = (3, 0): Morton 5, of 16 bits.
        let child = view(&json, bin, &json["childSubtreeAvailability"]["bitstream"]);
        assert_eq!(child, &[0b0010_0000, 0]);
        // Rows in bit order: the root (1), then (1, 2) at Morton 1 (2), then (0, 3) (3).
        let table = &json["propertyTables"][json["tileMetadata"].as_u64().unwrap() as usize];
        assert_eq!(table["class"], "tile");
        assert_eq!(table["count"], 3);
        let p = &table["properties"];
        assert_eq!(
            f64s(view(&json, bin, &p["minimumHeight"]["values"])),
            [1.0, 2.0, 3.0]
        );
        assert_eq!(
            f64s(view(&json, bin, &p["maximumHeight"]["values"])),
            [1.5, 2.5, 3.5]
        );
        assert_eq!(
            f64s(view(&json, bin, &p["boundingSphere"]["values"]))[4..8],
            [2.0, 4.0, 6.0, 8.0]
        );
        assert_eq!(
            f64s(view(&json, bin, &p["horizonOcclusionPoint"]["values"]))[6..],
            [-3.0, -6.0, -9.0]
        );
        // A subtree without child subtrees says so by a constant.
        let (leaf, _) = chunks(&subtree(at(3, 3, 4), 2, &info));
        assert_eq!(leaf["childSubtreeAvailability"], json!({"constant": 0}));
    }

    #[test]
    fn the_schema_gives_the_semantics_the_terrain_provider_reads() {
        let s = schema();
        let props = &s["classes"]["tile"]["properties"];
        for (name, semantic) in [
            ("minimumHeight", "TILE_MINIMUM_HEIGHT"),
            ("maximumHeight", "TILE_MAXIMUM_HEIGHT"),
            ("boundingSphere", "TILE_BOUNDING_SPHERE"),
            ("horizonOcclusionPoint", "TILE_HORIZON_OCCLUSION_POINT"),
        ] {
            assert_eq!(props[name]["semantic"], semantic);
        }
        assert_eq!(props["boundingSphere"]["count"], 4);
        // tileset.json: two implicit children with subtrees every SUBTREE_LEVELS (fewer when
        // the tileset is shallower), the schema, and a subtree file per subtree root.
        let mut info = BTreeMap::new();
        for root in 0..2 {
            info.insert(
                Implicit {
                    root,
                    ..at(0, 0, 0)
                },
                row(0.0),
            );
        }
        info.insert(at(1, 1, 0), row(5.0));
        let files = tileset_files(&info, 10.0, json!({}));
        let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
        assert_eq!(
            names,
            [
                "tileset.json",
                "0/subtrees/0/0/0.subtree",
                "1/subtrees/0/0/0.subtree"
            ]
        );
        let t: Value = serde_json::from_slice(&files[0].1).unwrap();
        assert_eq!(t["asset"]["version"], "1.1");
        let children = t["root"]["children"].as_array().unwrap();
        assert_eq!(children.len(), 2);
        assert_eq!(children[1]["implicitTiling"]["subtreeLevels"], 2);
        assert_eq!(children[1]["implicitTiling"]["availableLevels"], 2);
        assert_eq!(children[1]["content"]["uri"], "1/{level}/{x}/{y}.glb");
        assert_eq!(t["root"]["boundingVolume"]["region"][5], 5.5);
    }

    /// A glb's JSON chunk and binary chunk.
    fn glb_chunks(bytes: &[u8]) -> (Value, &[u8]) {
        assert_eq!(&bytes[..4], b"glTF");
        assert_eq!(
            u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
            bytes.len()
        );
        let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let doc: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        (doc, &bytes[28 + json_len..])
    }

    fn f32s_of(doc: &Value, bin: &[u8], accessor: usize) -> Vec<f32> {
        let view = &doc["bufferViews"]
            [doc["accessors"][accessor]["bufferView"].as_u64().unwrap() as usize];
        let off = view["byteOffset"].as_u64().unwrap() as usize;
        bin[off..off + view["byteLength"].as_u64().unwrap() as usize]
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    #[test]
    fn a_glb_places_its_positions_and_normals_by_the_node_matrix_in_y_up() {
        let positions = [[6.4e6, 1.0, 2.0], [6.4e6, 11.0, 2.0], [6.4e6, 1.0, 12.0]];
        let s = 0.5f64.sqrt();
        let normals = [[1.0, 0.0, 0.0], [s, s, 0.0], [s, 0.0, -s]];
        let edges = [vec![0, 2], vec![0, 1], vec![1, 2], vec![2]];
        let mesh = GlbMesh {
            positions: &positions,
            normals: &normals,
            triangles: &[[0, 1, 2]],
            edges: &edges,
            water: None,
        };
        let bytes = glb([6.4e6, 0.0, 0.0], &mesh);
        let (doc, bin) = glb_chunks(&bytes);
        let m: Vec<f64> = doc["nodes"][0]["matrix"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let prim = &doc["meshes"][0]["primitives"][0];
        let at = |name: &str| prim["attributes"][name].as_u64().unwrap() as usize;
        let pos = f32s_of(&doc, bin, at("POSITION"));
        let nor = f32s_of(&doc, bin, at("NORMAL"));
        for k in 0..3 {
            // Node frame, then y-up to z-up: (x, y, z) → (x, −z, y); normals turn alike.
            let q = [0, 1, 2].map(|a| f64::from(pos[3 * k + a]) + m[12 + a]);
            assert_eq!([q[0], -q[2], q[1]], positions[k]);
            let n = [0, 1, 2].map(|a| f64::from(nor[3 * k + a]));
            for (a, b) in [n[0], -n[2], n[1]].iter().zip(normals[k]) {
                assert!((a - b).abs() < 1e-6, "{n:?} is not {:?}", normals[k]);
            }
        }
        assert_eq!(prim["extensions"]["CESIUM_tile_edges"]["top"], 6);
        assert_eq!(doc["accessors"][6]["count"], 1);
        assert!(doc.get("extensions").is_none(), "no water mask asked for");
    }

    #[test]
    fn a_water_mask_is_a_png_property_texture_of_semantic_watermask() {
        let positions = [[6.4e6, 1.0, 2.0], [6.4e6, 11.0, 2.0], [6.4e6, 1.0, 12.0]];
        let normals = [[1.0, 0.0, 0.0]; 3];
        let edges = [vec![0, 2], vec![0, 1], vec![1, 2], vec![2]];
        let grid: Vec<u8> = (0..65536)
            .map(|i| if i % 7 == 0 { 255 } else { 0 })
            .collect();
        for (water, side) in [
            (WaterMask::Grid(grid.clone()), 256),
            (WaterMask::Uniform(255), 1),
        ] {
            let mesh = GlbMesh {
                positions: &positions,
                normals: &normals,
                triangles: &[[0, 1, 2]],
                edges: &edges,
                water: Some(&water),
            };
            let bytes = glb([6.4e6, 0.0, 0.0], &mesh);
            let (doc, bin) = glb_chunks(&bytes);
            let meta = &doc["extensions"]["EXT_structural_metadata"];
            let class = meta["propertyTextures"][0]["class"].as_str().unwrap();
            let props = &meta["schema"]["classes"][class]["properties"];
            assert_eq!(props["waterMask"]["semantic"], "WATERMASK");
            let texture = meta["propertyTextures"][0]["properties"]["waterMask"]["index"]
                .as_u64()
                .unwrap() as usize;
            let image = doc["textures"][texture]["source"].as_u64().unwrap() as usize;
            assert_eq!(doc["images"][image]["mimeType"], "image/png");
            let view =
                &doc["bufferViews"][doc["images"][image]["bufferView"].as_u64().unwrap() as usize];
            let off = view["byteOffset"].as_u64().unwrap() as usize;
            let png_bytes = &bin[off..off + view["byteLength"].as_u64().unwrap() as usize];
            let mut reader = png::Decoder::new(std::io::Cursor::new(png_bytes))
                .read_info()
                .unwrap();
            let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
            let info = reader.next_frame(&mut pixels).unwrap();
            assert_eq!((info.width, info.height), (side, side));
            match &water {
                WaterMask::Grid(g) => assert_eq!(&pixels[..info.buffer_size()], &g[..]),
                WaterMask::Uniform(b) => assert_eq!(pixels[0], *b),
            }
        }
    }
}
