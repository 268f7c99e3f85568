//! Tiled runs through the real binary: front.json of a tiled run, export of its members,
//! thread-count invariance, and a bad `--tile`.

use paretomesh::kept_codec;

mod common;
use common::cli::{data, paretomesh, scratch, text};

/// `run` on volcano 87×61 in tiles of 33 with `threads`, its front.json as JSON.
fn tiled_run(dir: &std::path::Path, threads: &str) -> serde_json::Value {
    let out_path = dir.join(format!("front-{threads}.json"));
    let out = paretomesh(&[
        "run",
        data("volcano_87x61.f32").to_str().unwrap(),
        "--algo",
        "memetic",
        "--evals",
        "1500",
        "--tile",
        "33",
        "--threads",
        threads,
        "--out",
        out_path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    serde_json::from_slice(&std::fs::read(out_path).unwrap()).unwrap()
}

#[test]
fn a_tiled_front_is_the_same_on_one_or_two_threads_and_exports_every_format() {
    let dir = scratch("run");
    let mut one = tiled_run(&dir, "1");
    let mut two = tiled_run(&dir, "2");
    assert!(
        one.get("front").is_none(),
        "a tiled front lists no kept set per member"
    );
    let members = one["tiled"]["members"].as_array().unwrap().len();
    assert!(members > 10);
    assert_eq!(one["tiled"]["tiles"].as_array().unwrap().len(), 3 * 2);
    for file in [&mut one, &mut two] {
        let object = file.as_object_mut().unwrap();
        object.remove("millis");
        object.remove("threads");
    }
    assert_eq!(one, two);
    let front = dir.join("front-1.json");
    for (selector, value, name) in [
        ("--member", "0", "first.ply"),
        ("--max-triangles", "600", "m.obj"),
        ("--tradeoff", "", "t.stl"),
        ("--member", &(members - 1).to_string(), "last.glb"),
    ] {
        let out_path = dir.join(name);
        let mut args = vec!["export", front.to_str().unwrap(), selector];
        if !value.is_empty() {
            args.push(value);
        }
        args.extend(["--out", out_path.to_str().unwrap()]);
        let out = paretomesh(&args);
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        assert!(std::fs::metadata(&out_path).unwrap().len() > 0);
    }
    // The first member has one corner-only mesh per tile: 2 triangles each, 4 kept points
    // per tile, shared ones once.
    let ply = std::fs::read_to_string(dir.join("first.ply")).unwrap();
    assert!(ply.contains("element face 12"), "{ply}");
    assert!(ply.contains("element vertex 12"), "{ply}");
    // The last member's mesh has the member's T, and a copy of the file with each tile's kept
    // sets as plain index arrays (the form of older files) exports the same mesh.
    let last_t = one["tiled"]["members"][members - 1]["T"].as_u64().unwrap();
    let ply_of = |front: &std::path::Path, name: &str| {
        let out_path = dir.join(name);
        let out = paretomesh(&[
            "export",
            front.to_str().unwrap(),
            "--member",
            &(members - 1).to_string(),
            "--out",
            out_path.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        // The comment names the front file; the rest is the mesh.
        let ply = std::fs::read_to_string(out_path).unwrap();
        ply.lines()
            .filter(|l| !l.starts_with("comment"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let packed = ply_of(&front, "last-packed.ply");
    assert!(
        packed.contains(&format!("element face {last_t}\n")),
        "{packed}"
    );
    let mut plain: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&front).unwrap()).unwrap();
    for tile in plain["tiled"]["tiles"].as_array_mut().unwrap() {
        let mut previous: Option<Vec<u32>> = None;
        let mut sets = Vec::new();
        for m in tile["members"].as_array().unwrap() {
            let kept = match (m.get("kept_packed"), m.get("kept_diff")) {
                (Some(p), None) => kept_codec::decode(p.as_str().unwrap()).unwrap(),
                (None, Some(d)) => kept_codec::toggle(
                    previous.as_ref().expect("a diff follows a member"),
                    &kept_codec::decode(d.as_str().unwrap()).unwrap(),
                ),
                _ => panic!("a tile member is packed or a diff: {m}"),
            };
            sets.push(serde_json::json!(kept));
            previous = Some(kept);
        }
        tile["members"] = serde_json::Value::Array(sets);
    }
    let plain_path = dir.join("plain.json");
    std::fs::write(&plain_path, serde_json::to_vec(&plain).unwrap()).unwrap();
    assert!(
        std::fs::metadata(&plain_path).unwrap().len() > std::fs::metadata(&front).unwrap().len()
    );
    assert!(ply_of(&plain_path, "last-plain.ply") == packed);
}

#[test]
fn a_tile_too_small_is_refused_before_any_work_and_writes_nothing() {
    let dir = scratch("small");
    let out_path = dir.join("front.json");
    let out = paretomesh(&[
        "run",
        data("volcano_87x61.f32").to_str().unwrap(),
        "--tile",
        "5",
        "--out",
        out_path.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("--tile") && stderr.contains("at least 33"),
        "{stderr}"
    );
    assert!(!out_path.exists());
}

#[test]
fn a_grid_within_the_tile_size_runs_untiled() {
    let dir = scratch("untiled");
    let out_path = dir.join("front.json");
    let out = paretomesh(&[
        "run",
        data("volcano_33x33.f32").to_str().unwrap(),
        "--algo",
        "greedy",
        "--out",
        out_path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let file: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&out_path).unwrap()).unwrap();
    assert!(file.get("tiled").is_none() && file["front"].as_array().is_some());
    // No temporary file is left beside it.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

#[test]
fn eval_scores_given_triangles_as_it_scores_their_kept_set() {
    let grid = data("jacksboro_33x33.f32");
    let grid = grid.to_str().unwrap();
    let dir = scratch("eval");
    let kept_path = dir.join("kept.json");
    std::fs::write(&kept_path, "[100, 200, 300, 500, 700]").unwrap();
    let by_kept = paretomesh(&["eval", grid, "--keep", kept_path.to_str().unwrap()]);
    assert!(by_kept.status.success(), "{}", text(&by_kept.stderr));
    let by_kept: serde_json::Value = serde_json::from_slice(&by_kept.stdout).unwrap();
    let triangles_path = dir.join("triangles.json");
    std::fs::write(&triangles_path, by_kept["triangles"].to_string()).unwrap();
    let by_triangles = paretomesh(&[
        "eval",
        grid,
        "--triangles",
        triangles_path.to_str().unwrap(),
    ]);
    assert!(
        by_triangles.status.success(),
        "{}",
        text(&by_triangles.stderr)
    );
    let by_triangles: serde_json::Value = serde_json::from_slice(&by_triangles.stdout).unwrap();
    for field in ["E_sum", "E_max", "T"] {
        assert_eq!(by_kept[field], by_triangles[field], "{field}");
    }
}

/// Every file under `dir`, by its path relative to `dir`.
fn files(dir: &std::path::Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let name = path.strip_prefix(dir).unwrap().display().to_string();
                out.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    out
}

#[test]
fn tiles_from_a_nodata_dem_read_by_windows_equal_tiles_from_its_front() {
    // `tiles DEM` runs the tiles from the GeoTIFF's windows (nodata filled window by window)
    // before reading the grid for the pyramid; `run` then `tiles front.json` takes the same
    // front, so every file of the two pyramids is the same.
    let dir = scratch("tiles-windows");
    let dem = data("volcano_87x61_int16_lzw_nodata.tif");
    let front = dir.join("front.json");
    let common = ["--algo", "greedy", "--tile", "33", "--threads", "2"];
    let mut run = vec![
        "run",
        dem.to_str().unwrap(),
        "--out",
        front.to_str().unwrap(),
    ];
    run.extend(common);
    let out = paretomesh(&run);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&front).unwrap()).unwrap();
    let note = json["grid"]["source"]
        .as_str()
        .unwrap_or_default()
        .to_string();
    assert!(note.contains("14 nodata cells"), "{json}");
    let (a, b) = (dir.join("from-front"), dir.join("from-dem"));
    for (input, out_dir) in [(&front, &a), (&dem, &b)] {
        let mut args = vec![
            "tiles",
            input.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
            "--levels",
            "3",
        ];
        if input == &dem {
            args.extend(common);
        }
        let out = paretomesh(&args);
        assert!(out.status.success(), "{}", text(&out.stderr));
    }
    let (fa, fb) = (files(&a), files(&b));
    assert!(fa.len() >= 21, "{}", fa.len());
    assert_eq!(fa, fb);
}

#[test]
fn tiles_of_a_dem_take_a_greedy_max_error_fraction_and_refuse_it_elsewhere() {
    let dir = scratch("tiles-fraction");
    let dem = data("volcano_87x61_int16_lzw_nodata.tif");
    let out = dir.join("memetic");
    let refused = paretomesh(&[
        "tiles",
        dem.to_str().unwrap(),
        "--tile",
        "33",
        "--max-error-fraction",
        "0.01",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!refused.status.success());
    let message = text(&refused.stderr);
    assert!(
        message.contains("--max-error-fraction does not apply to --algo memetic"),
        "{message}"
    );
    assert!(!out.exists());
    // A greedy run stopped at 5 % of the z range keeps fewer triangles than one of every point.
    let triangles = |fraction: Option<&str>| {
        let out = dir.join(format!("greedy-{}", fraction.unwrap_or("all")));
        let mut args = vec![
            "tiles",
            dem.to_str().unwrap(),
            "--algo",
            "greedy",
            "--tile",
            "33",
            "--levels",
            "2",
            "--out",
            out.to_str().unwrap(),
        ];
        if let Some(f) = fraction {
            args.extend(["--max-error-fraction", f]);
        }
        let run = paretomesh(&args);
        let log = text(&run.stderr);
        assert!(run.status.success(), "{log}");
        log.lines()
            .filter(|l| l.starts_with("level "))
            .map(|l| l.to_string())
            .collect::<Vec<_>>()
    };
    let (stopped, all) = (triangles(Some("0.05")), triangles(None));
    assert_eq!(stopped.len(), 2);
    assert_ne!(stopped, all);
}

#[test]
fn a_dem_over_the_importers_limits_is_refused_before_its_tiles_run() {
    // `tiles DEM` reads the grid whole for the pyramid after running the tiles from windows:
    // a grid it could not read is refused first, with the importer's message.
    use tiff::encoder::{TiffEncoder, colortype};
    let dir = scratch("tiles-too-wide");
    let (w, h) = (16_385u32, 3u32);
    let z: Vec<f32> = (0..w * h).map(|i| (i % 97) as f32).collect();
    let dem = dir.join("wide.tif");
    let mut file = std::fs::File::create(&dem).unwrap();
    TiffEncoder::new(&mut file)
        .unwrap()
        .write_image::<colortype::Gray32Float>(w, h, &z)
        .unwrap();
    let out_dir = dir.join("out");
    let out = paretomesh(&[
        "tiles",
        dem.to_str().unwrap(),
        "--algo",
        "greedy",
        "--tile",
        "33",
        "--levels",
        "1",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let log = text(&out.stderr);
    assert!(!out.status.success());
    assert!(log.contains("16384 per side"), "{log}");
    assert!(!log.contains("tiles run"), "{log}");
    assert!(!out_dir.exists());
}
