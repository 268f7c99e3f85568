//! Terrain tilesets: quantized-mesh tiles of a DEM read back by the crate's decoder, their
//! shared tile edges at every level (the crack check), heights against the DEM, layer.json's
//! availability; 3D Tiles levels chosen from a tiled front, their shared edges; and the
//! specific messages for bad input.
#![cfg(not(target_arch = "wasm32"))]

use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::pyramid::Level;
use paretomesh::pyramid::tile_mesh;
use paretomesh::pyramid::tiled_levels;
use paretomesh::pyramid::with_border_points;
use paretomesh::terrain::{
    DecodedTile, RasterOptions, Scheme, TerrainOptions, build_terrain, decode_tile, reproject,
};
use paretomesh::tiling::{TilePlan, run_tiled};
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::io::Read;
use std::path::PathBuf;

mod common;
use common::cli::{data, paretomesh, scratch};

/// A scratch folder emptied first, so that no file of an earlier use of the name is counted.
fn fresh(name: &str) -> PathBuf {
    let dir = scratch(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn gunzip(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .read_to_end(&mut out)
        .unwrap();
    out
}

/// The quantized-mesh tileset of the UTM DEM (under a triangle budget, if given), decoded: layer.json and every tile by (z, x, y).
fn tileset(
    scheme: Scheme,
    max_triangles: Option<u64>,
) -> (Value, BTreeMap<(u32, u64, u64), DecodedTile>) {
    let dem = import::load(&data("jacksboro_65x65_utm16n.tif")).unwrap();
    let raster = reproject(
        &dem,
        RasterOptions {
            scheme,
            geoid: false,
            cells_per_tile: 32,
            levels: Some(3),
        },
    )
    .unwrap();
    let plan = TilePlan::new(raster.hf.width(), raster.hf.height(), 129).unwrap();
    let config = greedy_config();
    let front = run_tiled(&raster.hf, &plan, &config, 1, 2).unwrap();
    let built = build_terrain(
        &raster,
        &front,
        TerrainOptions {
            water_mask: true,
            finest_error: None,
            max_triangles,
        },
        &|_, _| {},
    )
    .unwrap();
    let mut tiles = BTreeMap::new();
    let mut layer = Value::Null;
    for (path, bytes) in built.files {
        if path == "layer.json" {
            layer = serde_json::from_slice(&bytes).unwrap();
            continue;
        }
        let parts: Vec<u64> = path
            .trim_end_matches(".terrain")
            .split('/')
            .map(|p| p.parse().unwrap())
            .collect();
        let tile = decode_tile(&gunzip(&bytes)).unwrap();
        tiles.insert((parts[0] as u32, parts[1], parts[2]), tile);
    }
    (layer, tiles)
}

/// An edge's vertices as (position along the edge, height), sorted.
fn edge(tile: &DecodedTile, side: usize) -> Vec<(u16, f64)> {
    let mut out: Vec<(u16, f64)> = tile.edges[side]
        .iter()
        .map(|&i| {
            let i = i as usize;
            let along = if side.is_multiple_of(2) {
                tile.v[i]
            } else {
                tile.u[i]
            };
            (along, tile.height_of(i))
        })
        .collect();
    out.sort_by(|a, b| a.partial_cmp(b).unwrap());
    out
}

#[test]
fn adjacent_terrain_tiles_share_their_border_vertices_at_every_level() {
    // The halving bounds on both schemes, then a budget of 60 % of their triangles.
    let (_, halving) = tileset(Scheme::Geographic, None);
    let all: usize = halving.values().map(|t| t.triangles.len()).sum();
    let budget = all as u64 * 6 / 10;
    for (scheme, max_triangles) in [
        (Scheme::Geographic, None),
        (Scheme::Mercator, None),
        (Scheme::Geographic, Some(budget)),
    ] {
        let (layer, tiles) = tileset(scheme, max_triangles);
        if let Some(n) = max_triangles {
            let spent: usize = tiles.values().map(|t| t.triangles.len()).sum();
            assert!(spent as u64 <= n, "{spent} triangles > {n}");
            assert!(
                spent as u64 > n / 2,
                "{spent} triangles of {n}: the budget is spent"
            );
        }
        let mut pairs = 0;
        for (&(z, x, y), tile) in &tiles {
            // Every edge list holds exactly the vertices on that edge.
            for (side, list) in tile.edges.iter().enumerate() {
                let on: BTreeSet<u32> = (0..tile.u.len() as u32)
                    .filter(|&i| {
                        let (u, v) = (tile.u[i as usize], tile.v[i as usize]);
                        [u == 0, v == 0, u == 32767, v == 32767][side]
                    })
                    .collect();
                assert_eq!(list.iter().copied().collect::<BTreeSet<_>>(), on);
            }
            // Every triangle is counter-clockwise in (u, v), as the format requires.
            for t in &tile.triangles {
                let p = t.map(|i| (f64::from(tile.u[i as usize]), f64::from(tile.v[i as usize])));
                let area =
                    (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[2].0 - p[0].0) * (p[1].1 - p[0].1);
                assert!(area > 0.0, "{z}/{x}/{y}: {t:?}");
            }
            let tolerance = |a: &DecodedTile, b: &DecodedTile| {
                f64::from(a.max_height - a.min_height + b.max_height - b.min_height) / 32767.0
                    + 1e-3
            };
            // East neighbour: this tile's east edge is its west edge; north: north on south.
            for (dx, dy, mine, theirs) in [(1, 0, 2, 0), (0, 1, 3, 1)] {
                let Some(other) = tiles.get(&(z, x + dx, y + dy)) else {
                    continue;
                };
                let (a, b) = (edge(tile, mine), edge(other, theirs));
                assert_eq!(
                    a.iter().map(|p| p.0).collect::<Vec<_>>(),
                    b.iter().map(|p| p.0).collect::<Vec<_>>(),
                    "{scheme:?} {z}/{x}/{y} and its neighbour"
                );
                let tol = tolerance(tile, other);
                for (p, q) in a.iter().zip(&b) {
                    assert!((p.1 - q.1).abs() <= tol, "{z}/{x}/{y}: {} vs {}", p.1, q.1);
                }
                pairs += 1;
            }
        }
        assert!(pairs >= 20, "{pairs} neighbour pairs checked");
        // Each DEM level's geometric error falls with depth.
        let errors: Vec<f64> = layer["paretomesh"]["levels"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|l| !l["bound"].is_null())
            .map(|l| l["geometricError"].as_f64().unwrap())
            .collect();
        assert_eq!(errors.len(), 3);
        assert!(errors.windows(2).all(|e| e[1] < e[0]), "{errors:?}");
        // layer.json lists every tile written, and only those.
        let mut listed = BTreeSet::new();
        for (z, ranges) in layer["available"].as_array().unwrap().iter().enumerate() {
            for r in ranges.as_array().unwrap() {
                let g = |k: &str| r[k].as_u64().unwrap();
                for x in g("startX")..=g("endX") {
                    for y in g("startY")..=g("endY") {
                        listed.insert((z as u32, x, y));
                    }
                }
            }
        }
        assert_eq!(listed, tiles.keys().copied().collect::<BTreeSet<_>>());
        let roots = if scheme == Scheme::Geographic { 2 } else { 1 };
        assert_eq!(tiles.keys().filter(|k| k.0 == 0).count(), roots);
        assert_eq!(layer["projection"], scheme_name(scheme));
        // Each tile's metadata names the children that exist.
        for (&(z, x, y), tile) in &tiles {
            let children: Vec<_> = [(0, 0), (1, 0), (0, 1), (1, 1)]
                .iter()
                .filter(|(dx, dy)| tiles.contains_key(&(z + 1, 2 * x + dx, 2 * y + dy)))
                .collect();
            match &tile.metadata {
                None => assert!(children.is_empty(), "{z}/{x}/{y}"),
                Some(json) => {
                    let m: Value = serde_json::from_str(json).unwrap();
                    let n: u64 = m["available"][0]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|r| {
                            let g = |k: &str| r[k].as_u64().unwrap();
                            (g("endX") - g("startX") + 1) * (g("endY") - g("startY") + 1)
                        })
                        .sum();
                    assert_eq!(n as usize, children.len(), "{z}/{x}/{y}");
                }
            }
            assert!(tile.water_mask_bytes == Some(1) || tile.water_mask_bytes == Some(65536));
            // Normals are unit vectors.
            assert!(tile.normals.as_ref().unwrap().iter().all(|n| {
                ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-9
            }));
        }
    }
}

fn scheme_name(s: Scheme) -> &'static str {
    s.projection()
}

#[test]
fn three_d_tiles_levels_from_a_tiled_front_meet_their_bounds_without_cracks() {
    let hf: Heightfield = import::load(&data("volcano_87x61.f32")).unwrap();
    let plan = TilePlan::new(hf.width(), hf.height(), 33).unwrap();
    assert!(plan.len() > 1);
    let front = run_tiled(&hf, &plan, &greedy_config(), 1, 2).unwrap();
    let levels = tiled_levels(&front, &hf, 3, Some(1.0)).unwrap();
    for (depth, level) in levels.iter().enumerate() {
        assert!(level.score.e_max <= level.bound);
        let quad = Level::new(hf.width(), hf.height(), depth as u32);
        let with_borders = with_border_points(&hf, &quad, &level.kept, level.score.e_max);
        let shares = quad.share_out(&with_borders);
        let tiles = quad.tiles();
        let meshes: Vec<_> = tiles
            .iter()
            .zip(&shares)
            .map(|(t, s)| tile_mesh(&hf, t, s).unwrap())
            .collect();
        let side = quad.side();
        for (i, tile) in tiles.iter().enumerate() {
            let on = |m: &paretomesh::pyramid::TileMesh, keep: &dyn Fn(usize, usize) -> bool| {
                m.vertices
                    .iter()
                    .copied()
                    .filter(|&g| keep(g as usize % hf.width(), g as usize / hf.width()))
                    .collect::<Vec<u32>>()
            };
            if tile.x + 1 < side {
                let x = tile.columns.1;
                let line = |gx: usize, _| gx == x;
                assert_eq!(
                    on(&meshes[i], &line),
                    on(&meshes[i + 1], &line),
                    "level {depth}"
                );
            }
            if tile.y + 1 < side {
                let y = tile.rows.1;
                let line = |_, gy: usize| gy == y;
                assert_eq!(
                    on(&meshes[i], &line),
                    on(&meshes[i + side], &line),
                    "level {depth}"
                );
            }
        }
    }
}

fn fails(args: &[&str]) -> String {
    let out = paretomesh(args);
    assert!(!out.status.success(), "{args:?} succeeded");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn bad_input_gets_a_specific_message_and_no_tileset() {
    let dir = fresh("bad");
    let out = dir.join("tiles");
    let out_s = out.to_str().unwrap();
    let qm = ["--format", "quantized-mesh", "--algo", "greedy"];
    // A GeoTIFF with no georeferencing at all, and one with no coordinate system.
    let m = fails(
        &[
            &[
                "tiles",
                data("camera_33x33_float64.tif").to_str().unwrap(),
                "--out",
                out_s,
            ],
            &qm[..],
        ]
        .concat(),
    );
    assert!(m.contains("no georeferencing"), "{m}");
    let m = fails(
        &[
            &[
                "tiles",
                data("volcano_87x61_int16_lzw_nodata.tif").to_str().unwrap(),
                "--out",
                out_s,
            ],
            &qm[..],
        ]
        .concat(),
    );
    assert!(m.contains("names no EPSG coordinate system"), "{m}");
    // An EPSG code the projection library does not know (32616 patched to 32600).
    let mut bytes = std::fs::read(data("jacksboro_65x65_utm16n.tif")).unwrap();
    let at: Vec<usize> = (0..bytes.len() - 1)
        .filter(|&i| bytes[i..i + 2] == 32616u16.to_le_bytes())
        .collect();
    assert_eq!(at.len(), 1);
    bytes[at[0]..at[0] + 2].copy_from_slice(&32600u16.to_le_bytes());
    let unknown = dir.join("unknown.tif");
    std::fs::write(&unknown, &bytes).unwrap();
    let m = fails(
        &[
            &["tiles", unknown.to_str().unwrap(), "--out", out_s],
            &qm[..],
        ]
        .concat(),
    );
    assert!(
        m.contains("EPSG:32600 is not in the projection library"),
        "{m}"
    );
    // A truncated file.
    let whole = std::fs::read(data("jacksboro_65x65_utm16n.tif")).unwrap();
    let cut = dir.join("cut.tif");
    std::fs::write(&cut, &whole[..whole.len() / 2]).unwrap();
    let m = fails(&[&["tiles", cut.to_str().unwrap(), "--out", out_s], &qm[..]].concat());
    assert!(m.contains("truncated") || m.contains("ends"), "{m}");
    assert!(!out.exists());
    // An output folder that is a file.
    std::fs::write(&out, b"not a folder").unwrap();
    let m = fails(
        &[
            &[
                "tiles",
                data("jacksboro_65x65_utm16n.tif").to_str().unwrap(),
                "--out",
                out_s,
            ],
            &qm[..],
        ]
        .concat(),
    );
    assert!(m.contains("is a file"), "{m}");
    assert_eq!(std::fs::read(&out).unwrap(), b"not a folder");
    // A front for quantized-mesh.
    std::fs::remove_file(&out).unwrap();
    let m = fails(
        &[
            &[
                "tiles",
                dir.join("front.json").to_str().unwrap(),
                "--out",
                out_s,
            ],
            &qm[..],
        ]
        .concat(),
    );
    assert!(m.contains("give the DEM itself"), "{m}");
    // No partial folder is left beside the output.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("partial"))
        .collect();
    assert!(left.is_empty());
}

#[test]
fn a_dem_and_its_tiled_front_give_3d_tiles_and_quantized_mesh_through_the_cli() {
    let dir = fresh("cli");
    let dem = data("jacksboro_65x65_utm16n.tif");
    let front = dir.join("front.json");
    let run = paretomesh(&[
        "run",
        dem.to_str().unwrap(),
        "--algo",
        "greedy",
        "--tile",
        "33",
        "--out",
        front.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let pyramid = dir.join("pyramid");
    let out = paretomesh(&[
        "tiles",
        front.to_str().unwrap(),
        "--out",
        pyramid.to_str().unwrap(),
        "--levels",
        "3",
    ]);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{log}");
    assert!(log.contains("tiles written: 21 of 21"), "{log}");
    let tileset: Value =
        serde_json::from_slice(&std::fs::read(pyramid.join("tileset.json")).unwrap()).unwrap();
    assert_eq!(tileset["root"]["children"].as_array().unwrap().len(), 4);
    // Straight from the DEM, into an existing folder, which is replaced.
    let qm = dir.join("qm");
    std::fs::create_dir_all(qm.join("stale")).unwrap();
    let out = paretomesh(&[
        "tiles",
        dem.to_str().unwrap(),
        "--format",
        "quantized-mesh",
        "--scheme",
        "mercator",
        "--algo",
        "greedy",
        "--levels",
        "2",
        "--geoid",
        "egm96",
        "--out",
        qm.to_str().unwrap(),
    ]);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{log}");
    assert!(log.contains("tiles run: 1 of 1"), "{log}");
    assert!(!qm.join("stale").exists());
    let layer: Value =
        serde_json::from_slice(&std::fs::read(qm.join("layer.json")).unwrap()).unwrap();
    assert_eq!(layer["projection"], "EPSG:3857");
    assert_eq!(layer["format"], "quantized-mesh-1.0");
    let root = decode_tile(&gunzip(&std::fs::read(qm.join("0/0/0.terrain")).unwrap())).unwrap();
    assert_eq!(root.triangles.len(), 128);
}

/// Greedy insertion recording 64 meshes, the method these tests run tile by tile.
fn greedy_config() -> paretomesh::catalogue::Config {
    paretomesh::catalogue::Config::from_json(
        paretomesh::catalogue::Algorithm::Greedy,
        &serde_json::json!({"records": 64}),
    )
    .unwrap()
}
