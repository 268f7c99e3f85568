//! 3D Tiles terrain (`build_3dtiles_terrain`): the glbs read back, adjacent tiles' border
//! vertices coincide at every level (the crack check), the subtrees list every tile written,
//! the levels' errors fall with depth, and Web Mercator is refused.
#![cfg(not(target_arch = "wasm32"))]

use paretomesh::import;
use paretomesh::terrain::{
    RasterOptions, Scheme, TerrainOptions, build_3dtiles_terrain, reproject,
};
use paretomesh::tiling::{TilePlan, run_tiled};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// A glb's ECEF positions and its west, south, east and north edge vertices.
struct Tile {
    positions: Vec<[f64; 3]>,
    edges: [Vec<u32>; 4],
}

fn u32_at(b: &[u8], at: usize) -> usize {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap()) as usize
}

fn read_glb(bytes: &[u8]) -> Tile {
    assert_eq!(&bytes[..4], b"glTF");
    let json_len = u32_at(bytes, 12);
    let doc: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = &bytes[28 + json_len..];
    let accessor = |k: usize| {
        let a = &doc["accessors"][k];
        let v = &doc["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        let off = v["byteOffset"].as_u64().unwrap() as usize;
        (&bin[off..], a["count"].as_u64().unwrap() as usize)
    };
    let m: Vec<f64> = doc["nodes"][0]["matrix"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let (pos, n) = accessor(0);
    let positions = (0..n)
        .map(|i| {
            let c = |a: usize| {
                f64::from(f32::from_le_bytes(
                    pos[12 * i + 4 * a..12 * i + 4 * a + 4].try_into().unwrap(),
                )) + m[12 + a]
            };
            [c(0), -c(2), c(1)]
        })
        .collect();
    let ext = &doc["meshes"][0]["primitives"][0]["extensions"]["CESIUM_tile_edges"];
    let edges = ["left", "bottom", "right", "top"].map(|side| {
        let (b, n) = accessor(ext[side].as_u64().unwrap() as usize);
        (0..n).map(|i| u32_at(b, 4 * i) as u32).collect()
    });
    Tile { positions, edges }
}

#[test]
fn three_d_tiles_terrain_tiles_share_border_vertices_and_subtrees_list_them() {
    let dem = import::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/jacksboro_65x65_utm16n.tif"),
    )
    .unwrap();
    let raster = reproject(
        &dem,
        RasterOptions {
            scheme: Scheme::Geographic,
            geoid: false,
            cells_per_tile: 32,
            levels: Some(3),
        },
    )
    .unwrap();
    let plan = TilePlan::new(raster.hf.width(), raster.hf.height(), 129).unwrap();
    let config = paretomesh::catalogue::Config::from_json(
        paretomesh::catalogue::Algorithm::Greedy,
        &serde_json::json!({"records": 64}),
    )
    .unwrap();
    let front = run_tiled(&raster.hf, &plan, &config, 1, 2).unwrap();
    let options = TerrainOptions {
        water_mask: false,
        finest_error: None,
        max_triangles: None,
    };
    let built = build_3dtiles_terrain(&raster, &front, options, &|_, _| {}).unwrap();
    let mut tiles = BTreeMap::new();
    let mut subtree_count = 0;
    for (path, bytes) in &built.files {
        if let Some(glb) = path.strip_suffix(".glb") {
            let k: Vec<u64> = glb.split('/').map(|p| p.parse().unwrap()).collect();
            tiles.insert((k[0], k[1], k[2], k[3]), read_glb(bytes));
        } else if path.ends_with(".subtree") {
            let json_len = u64::from_le_bytes(bytes[8..16].try_into().unwrap()) as usize;
            let doc: Value = serde_json::from_slice(&bytes[24..24 + json_len]).unwrap();
            subtree_count += doc["tileAvailability"]["availableCount"].as_u64().unwrap();
        }
    }
    // Every tile is in exactly one subtree; both hemispheres' roots exist.
    assert_eq!(subtree_count as usize, tiles.len());
    assert!(tiles.contains_key(&(0, 0, 0, 0)) && tiles.contains_key(&(1, 0, 0, 0)));
    let mut pairs = 0;
    for (&(root, level, x, y), tile) in &tiles {
        // Every edge of the quad has at least its two corners.
        assert!(tile.edges.iter().all(|e| e.len() >= 2));
        for (dx, dy, mine, theirs) in [(1, 0, 2, 0), (0, 1, 3, 1)] {
            let Some(other) = tiles.get(&(root, level, x + dx, y + dy)) else {
                continue;
            };
            let side = |t: &Tile, s: usize| {
                let mut p: Vec<[f64; 3]> = t.edges[s]
                    .iter()
                    .map(|&i| t.positions[i as usize])
                    .collect();
                p.sort_by(|a, b| a.partial_cmp(b).unwrap());
                p
            };
            let (a, b) = (side(tile, mine), side(other, theirs));
            assert_eq!(
                a.len(),
                b.len(),
                "{root}/{level}/{x}/{y}: edge vertex counts"
            );
            // f32 positions about each tile's centre: a few millimetres at these sizes.
            for (p, q) in a.iter().zip(&b) {
                let d = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
                assert!(d < 0.05, "{root}/{level}/{x}/{y}: {p:?} vs {q:?}");
            }
            pairs += 1;
        }
    }
    assert!(pairs >= 20, "{pairs} neighbour pairs checked");
    // The levels' geometric errors fall with depth.
    let errors: Vec<f64> = built
        .levels
        .iter()
        .filter(|l| l.bound.is_some())
        .map(|l| l.error)
        .collect();
    assert_eq!(errors.len(), 3);
    assert!(errors.windows(2).all(|e| e[1] < e[0]), "{errors:?}");
    let tileset: Value = serde_json::from_slice(&built.files[0].1).unwrap();
    assert_eq!(built.files[0].0, "tileset.json");
    assert_eq!(
        tileset["extras"]["paretomesh"]["levels"]
            .as_array()
            .unwrap()
            .len(),
        built.levels.len()
    );
    // Web Mercator is refused with a message naming the scheme.
    let mercator = reproject(
        &dem,
        RasterOptions {
            scheme: Scheme::Mercator,
            geoid: false,
            cells_per_tile: 32,
            levels: Some(1),
        },
    )
    .unwrap();
    let err = build_3dtiles_terrain(&mercator, &front, options, &|_, _| {})
        .err()
        .unwrap();
    assert!(err.contains("geographic"), "{err}");
}
