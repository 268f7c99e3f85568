//! `paretomesh tiles`: the 3D Tiles pyramid of a front, read back with independent readers (the
//! `gltf` crate, serde_json), its shared tile edges, its errors, and its place on the globe
//! against GDAL's and proj4rs's conversions.

use paretomesh::front_file::FrontFile;
use paretomesh::import;
use paretomesh::pyramid::{Frame, Level, MapSystem, ecef, tile_mesh, with_border_points};
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

mod common;
use common::cli::{data, paretomesh, scratch, text};

/// A greedy-insertion front of `grid` written to `dir`/front.json.
fn front(dir: &Path, grid: &Path) -> PathBuf {
    let path = dir.join("front.json");
    let out = paretomesh(&[
        "run",
        grid.to_str().unwrap(),
        "--algo",
        "greedy",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    path
}

/// Runs `tiles` into `dir`/tiles and returns that folder and its tileset.
fn pyramid(dir: &Path, front: &Path, extra: &[&str]) -> (PathBuf, Value) {
    let out_dir = dir.join("tiles");
    let mut args = vec![
        "tiles",
        front.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let out = paretomesh(&args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let tileset = serde_json::from_slice(&std::fs::read(out_dir.join("tileset.json")).unwrap())
        .expect("tileset.json is JSON");
    (out_dir, tileset)
}

/// Every tile of the tree with its depth, parents before children.
fn walk(tile: &Value, depth: usize, out: &mut Vec<(usize, Value)>) {
    out.push((depth, tile.clone()));
    if let Some(children) = tile["children"].as_array() {
        for child in children {
            walk(child, depth + 1, out);
        }
    }
}

#[test]
fn the_tileset_has_the_3d_tiles_basics_and_every_tile_reads_back() {
    let dir = scratch("basics");
    let front = front(&dir, &data("jacksboro_65x65_utm16n.tif"));
    let (folder, tileset) = pyramid(&dir, &front, &["--levels", "4"]);
    assert_eq!(tileset["asset"]["version"], "1.1");
    assert!(tileset["geometricError"].as_f64().unwrap() > 0.0);
    let root = &tileset["root"];
    assert_eq!(root["transform"].as_array().unwrap().len(), 16);
    let frame = tileset["extras"]["frame"].as_str().unwrap();
    assert!(frame.contains("EPSG:32616"), "{frame}");
    let mut tiles = Vec::new();
    walk(root, 0, &mut tiles);
    // A full quadtree of four levels.
    for depth in 0..4 {
        let count = tiles.iter().filter(|(d, _)| *d == depth).count();
        assert_eq!(count, 1 << (2 * depth), "level {depth}");
    }
    let levels = tileset["extras"]["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 4);
    let file: FrontFile = serde_json::from_slice(&std::fs::read(&front).unwrap()).unwrap();
    let mut triangles_per_level = [0usize; 4];
    for (depth, tile) in &tiles {
        assert_eq!(tile["refine"], "REPLACE");
        let bounds = tile["boundingVolume"]["box"].as_array().unwrap();
        assert_eq!(bounds.len(), 12);
        assert!(bounds.iter().all(|v| v.as_f64().unwrap().is_finite()));
        assert!(tile["geometricError"].as_f64().unwrap() >= 0.0);
        match tile["children"].as_array() {
            Some(children) => assert_eq!(children.len(), 4),
            None => assert_eq!(*depth, 3),
        }
        let uri = tile["content"]["uri"].as_str().unwrap();
        let bytes = std::fs::read(folder.join(uri)).unwrap();
        let document = gltf::Gltf::from_slice(&bytes).expect("a valid glb");
        let mesh = document.meshes().next().unwrap();
        let primitive = mesh.primitives().next().unwrap();
        let blob = document.blob.as_deref();
        let reader = primitive.reader(|buffer| match buffer.source() {
            gltf::buffer::Source::Bin => blob,
            _ => None,
        });
        let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
        assert!(indices.iter().all(|&i| (i as usize) < positions.len()));
        assert_eq!(indices.len() % 3, 0);
        triangles_per_level[*depth] += indices.len() / 3;
        // The node's translation puts the tile near the frame's origin (the grid's centre),
        // in y-up: the grid spans about 30 km east and north and under 1 km up.
        let node = document.nodes().next().unwrap();
        let [x, y, z] = node.transform().decomposed().0;
        assert!(x.abs() < 16_000.0 && z.abs() < 16_000.0 && y.abs() < 1_000.0);
    }
    // The root is the coarsest member's own mesh; each finer level has more triangles.
    let root_member = levels[0]["member"].as_u64().unwrap() as usize;
    assert_eq!(
        triangles_per_level[0],
        file.front[root_member].solution.score.t
    );
    assert!(triangles_per_level.windows(2).all(|w| w[0] < w[1]));
    let ts: Vec<u64> = levels.iter().map(|l| l["T"].as_u64().unwrap()).collect();
    assert!(ts.windows(2).all(|w| w[0] < w[1]), "{ts:?}");
}

#[test]
fn geometric_errors_never_grow_down_the_tree_and_bound_each_level() {
    let dir = scratch("errors");
    let front = front(&dir, &data("volcano_87x61.f32"));
    let (_, tileset) = pyramid(&dir, &front, &["--levels", "4"]);
    fn check(tile: &Value) {
        let error = tile["geometricError"].as_f64().unwrap();
        for child in tile["children"].as_array().into_iter().flatten() {
            assert!(child["geometricError"].as_f64().unwrap() <= error);
            check(child);
        }
    }
    let root = &tileset["root"];
    check(root);
    assert!(
        tileset["geometricError"].as_f64().unwrap() >= root["geometricError"].as_f64().unwrap()
    );
    // The root shows a whole member: its error is at least that member's E_max.
    let coarsest = &tileset["extras"]["levels"][0];
    assert!(root["geometricError"].as_f64().unwrap() >= coarsest["E_max"].as_f64().unwrap());
    // An ungeoreferenced grid stays in its own coordinates.
    assert!(root.get("transform").is_none());
}

#[test]
fn neighbour_tiles_share_their_border_edges_exactly() {
    let dir = scratch("edges");
    let grid = data("volcano_87x61.f32");
    let front = front(&dir, &grid);
    let file: FrontFile = serde_json::from_slice(&std::fs::read(&front).unwrap()).unwrap();
    let hf = import::load(&grid).unwrap();
    let w = hf.width();
    let member = &file.front[file.front.len() / 2].solution;
    for depth in 1..=3 {
        let level = Level::new(w, hf.height(), depth);
        let kept = with_border_points(&hf, &level, &member.kept, member.score.e_max);
        assert!(member.kept.iter().all(|g| kept.binary_search(g).is_ok()));
        let shares = level.share_out(&kept);
        let tiles = level.tiles();
        let meshes: Vec<_> = tiles
            .iter()
            .zip(&shares)
            .map(|(t, s)| tile_mesh(&hf, t, s).unwrap())
            .collect();
        // The edges of a tile that lie on grid column `x` (or row `y`).
        let on_line = |i: usize, column: Option<usize>, row: Option<usize>| {
            let m = &meshes[i];
            let mut edges = BTreeSet::new();
            for t in &m.triangles {
                for k in 0..3 {
                    let (a, b) = (
                        m.vertices[t[k] as usize],
                        m.vertices[t[(k + 1) % 3] as usize],
                    );
                    let on = |g: u32| {
                        let (x, y) = (g as usize % w, g as usize / w);
                        column.is_none_or(|c| c == x) && row.is_none_or(|r| r == y)
                    };
                    if on(a) && on(b) {
                        edges.insert((a.min(b), a.max(b)));
                    }
                }
            }
            edges
        };
        let side = level.side();
        let mut compared = 0;
        for (i, tile) in tiles.iter().enumerate() {
            if tile.x + 1 < side {
                let line = tile.columns.1;
                let a = on_line(i, Some(line), None);
                let b = on_line(i + 1, Some(line), None);
                assert!(!a.is_empty());
                assert_eq!(a, b, "level {depth}, tiles {i} and {}", i + 1);
                compared += 1;
            }
            if tile.y + 1 < side {
                let line = tile.rows.1;
                let a = on_line(i, None, Some(line));
                let b = on_line(i + side, None, Some(line));
                assert!(!a.is_empty());
                assert_eq!(a, b, "level {depth}, tiles {i} and {}", i + side);
                compared += 1;
            }
        }
        assert_eq!(compared, 2 * side * (side - 1));
    }
}

/// ECEF positions GDAL 3.6 gives (`gdaltransform -s_srs EPSG:32616 -t_srs EPSG:4978`).
const GDAL_UTM16N: [([f64; 3], [f64; 3]); 3] = [
    (
        [731_000.0, 4_068_000.0, 0.0],
        [
            498_256.958_040_775,
            -5_093_682.083_659_81,
            3_793_388.254_885_42,
        ],
    ),
    (
        [746_000.0, 4_053_000.0, 500.0],
        [
            513_707.065_133_622,
            -5_101_796.108_839_84,
            3_781_327.126_534_54,
        ],
    ),
    (
        [761_000.0, 4_038_000.0, 1000.0],
        [
            529_153.821_720_809,
            -5_109_853.328_733_21,
            3_769_224.162_329_63,
        ],
    ),
];

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn utm_points_land_where_gdal_puts_them() {
    let utm = MapSystem::Utm {
        zone: 16,
        south: false,
    };
    for (map, want) in GDAL_UTM16N {
        let (lon, lat) = utm.to_lon_lat(map[0], map[1]);
        let got = ecef(lon, lat, map[2]);
        assert!(distance(got, want) < 0.01, "{map:?}: {got:?} vs {want:?}");
    }
    // Southern hemisphere, zone 33 (`gdaltransform -s_srs EPSG:32733 -t_srs EPSG:4978`).
    let (lon, lat) = MapSystem::Utm {
        zone: 33,
        south: true,
    }
    .to_lon_lat(612_345.0, 7_000_000.0);
    let want = [
        5_457_296.322_474_26,
        1_578_622.552_912_76,
        -2_889_894.626_854_55,
    ];
    assert!(distance(ecef(lon, lat, 100.0), want) < 0.01);
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn utm_inverse_agrees_with_proj4rs_across_a_zone() {
    use proj4rs::Proj;
    let from = Proj::from_proj_string("+proj=utm +zone=16 +datum=WGS84").unwrap();
    let to = Proj::from_proj_string("+proj=latlong +datum=WGS84").unwrap();
    let utm = MapSystem::Utm {
        zone: 16,
        south: false,
    };
    for easting in [170_000.0, 320_000.0, 500_000.0, 680_000.0, 830_000.0] {
        for northing in [10_000.0, 2_500_000.0, 4_068_000.0, 6_500_000.0, 8_800_000.0] {
            let mut point = (easting, northing, 0.0);
            proj4rs::transform::transform(&from, &to, &mut point).unwrap();
            let (lon, lat) = utm.to_lon_lat(easting, northing);
            let gap = distance(ecef(lon, lat, 0.0), ecef(point.0, point.1, 0.0));
            assert!(gap < 0.001, "({easting}, {northing}): {gap} m apart");
        }
    }
}

/// The ECEF position of a frame position, by the tileset's root transform.
fn through(transform: &[f64], p: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| {
        transform[r] * p[0] + transform[4 + r] * p[1] + transform[8 + r] * p[2] + transform[12 + r]
    })
}

#[test]
fn georeferenced_grids_sit_on_the_globe_where_their_corners_are() {
    // The UTM file's north-west sample centre is half a pixel (461.5 m / 2) inside its
    // corner; GDAL puts that centre here (EPSG:32616 → EPSG:4978).
    let hf = import::load(&data("jacksboro_65x65_utm16n.tif")).unwrap();
    let (frame, why) = Frame::of(&hf);
    assert_eq!(why, None);
    let transform = frame.transform().unwrap();
    let north_west = hf.index(0, hf.height() - 1);
    let world = hf.to_world(north_west, 0.0);
    let half = 30_000.0 / 65.0 / 2.0;
    assert!((world[0] - (731_000.0 + half)).abs() < 1e-6);
    assert!((world[1] - (4_068_000.0 - half)).abs() < 1e-6);
    let got = through(&transform, frame.place(world));
    let want = [
        498_494.076_006_704,
        -5_093_801.208_149_38,
        3_793_198.417_211_47,
    ];
    assert!(distance(got, want) < 0.01, "{got:?} vs {want:?}");

    // EPSG:4326: the south-west sample centre at 300 m (EPSG:4979 → EPSG:4978).
    let hf = import::load(&data("jacksboro_65x65_wgs84.tif")).unwrap();
    let (frame, why) = Frame::of(&hf);
    assert_eq!(why, None);
    let world = hf.to_world(0, 300.0);
    let want_lon_lat = (-84.41 + 0.33 / 65.0 / 2.0, 36.45 + 0.28 / 65.0 / 2.0);
    assert!((world[0] - want_lon_lat.0).abs() < 1e-9 && (world[1] - want_lon_lat.1).abs() < 1e-9);
    let got = through(&frame.transform().unwrap(), frame.place(world));
    let want = [
        500_577.567_281_419,
        -5_112_139.954_020_99,
        3_768_843.489_650_17,
    ];
    assert!(distance(got, want) < 0.01, "{got:?} vs {want:?}");
}

#[test]
fn bad_requests_are_refused_before_anything_is_written() {
    let dir = scratch("bad");
    let front = front(&dir, &data("jacksboro_33x33.f32"));
    let mut file: Value = serde_json::from_slice(&std::fs::read(&front).unwrap()).unwrap();
    let out_dir = dir.join("never");

    let out = paretomesh(&[
        "tiles",
        front.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--levels",
        "6",
    ]);
    assert!(!out.status.success());
    let message = text(&out.stderr);
    assert!(
        message.contains("too many levels") && message.contains("at most 5 levels"),
        "{message}"
    );
    assert!(!out_dir.exists());

    let members = file["front"].as_array().unwrap().len();
    let out = paretomesh(&[
        "tiles",
        front.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--levels",
        &(members + 1).to_string(),
    ]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("too many levels"));
    assert!(!out_dir.exists());

    file["front"].as_array_mut().unwrap().truncate(1);
    let one = dir.join("one.json");
    std::fs::write(&one, serde_json::to_vec(&file).unwrap()).unwrap();
    let out = paretomesh(&[
        "tiles",
        one.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let message = text(&out.stderr);
    assert!(message.contains("at least two members"), "{message}");
    assert!(!out_dir.exists());
}

#[test]
fn geotiffs_keep_the_epsg_code_of_their_coordinate_system() {
    let code = |name: &str| {
        import::load(&data(name))
            .unwrap()
            .georeference()
            .and_then(|g| g.epsg)
    };
    assert_eq!(code("jacksboro_65x65_utm16n.tif"), Some(32616));
    assert_eq!(code("jacksboro_65x65_wgs84.tif"), Some(4326));
    // Georeferenced without a coordinate system: the pyramid stays in map coordinates.
    assert_eq!(code("volcano_87x61_int16_lzw_nodata.tif"), None);
    let hf = import::load(&data("volcano_87x61_int16_lzw_nodata.tif")).unwrap();
    let (frame, why) = Frame::of(&hf);
    assert_eq!(frame, Frame::Local);
    assert!(why.unwrap().contains("names no EPSG"));
}
