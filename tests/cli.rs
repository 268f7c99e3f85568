//! The real `paretomesh` binary on fixtures and on bad files: output, exit status, messages.

mod common;
use common::cli::{data, paretomesh, scratch, text};

#[test]
fn info_reports_size_range_and_provenance() {
    let ply = data("volcano_87x61.ply");
    let out = paretomesh(&["info", ply.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("size: 87×61 = 5307 points"), "{stdout}");
    assert!(stdout.contains("z range: 94 .. 195"), "{stdout}");
    assert!(stdout.contains("exact 87×61 grid"), "{stdout}");
    assert!(stdout.contains("filled: 0"), "{stdout}");
}

#[test]
fn info_takes_the_import_options() {
    let ply = data("bunny_33x33.ply");
    let out = paretomesh(&[
        "info",
        ply.to_str().unwrap(),
        "--projection",
        "planar",
        "--grid-size",
        "20x10",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("size: 20×10 = 200 points"), "{stdout}");
    assert!(stdout.contains("placement: planar projection"), "{stdout}");
    // A malformed grid size is refused by the argument parser.
    let out = paretomesh(&["info", ply.to_str().unwrap(), "--grid-size", "20by10"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("129x129"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn eval_prints_the_score_as_json() {
    let dir = scratch("eval");
    let keep = dir.join("keep.json");
    // Only the corners of the 87×61 volcano: two triangles.
    std::fs::write(&keep, "[0, 86, 5220, 5306]").unwrap();
    let grid = data("volcano_87x61.f32");
    let out = paretomesh(&[
        "eval",
        grid.to_str().unwrap(),
        "--keep",
        keep.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["T"], 2);
    assert!(json["E_sum"].as_f64().unwrap() > 0.0);
}

#[test]
fn bad_files_print_a_message_and_exit_non_zero() {
    let dir = scratch("bad");
    // The volcano PLY cut in half: a truncated file.
    let whole = std::fs::read(data("volcano_87x61.ply")).unwrap();
    let cut = dir.join("cut.ply");
    std::fs::write(&cut, &whole[..whole.len() / 2]).unwrap();
    let out = paretomesh(&["info", cut.to_str().unwrap()]);
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(
        stderr.starts_with("error: ") && stderr.contains("truncated"),
        "{stderr}"
    );
    // An unknown kind of file, and one that does not exist.
    let notes = dir.join("notes.txt");
    std::fs::write(&notes, "hello").unwrap();
    let out = paretomesh(&["info", notes.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("unknown file type"));
    let out = paretomesh(&["eval", "missing.ply", "--keep", "-"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("cannot read missing.ply"));
}

#[test]
fn info_shows_a_geotiffs_georeferencing_and_nodata() {
    let tif = data("volcano_87x61_int16_lzw_nodata.tif");
    let out = paretomesh(&["info", tif.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("size: 87×61"), "{stdout}");
    assert!(stdout.contains("spacing: [10.0, 10.0]"), "{stdout}");
    assert!(
        stdout.contains("origin: [2667405.0, 6478105.0]"),
        "{stdout}"
    );
    assert!(
        stdout.contains("pixel scale (tag 33550): x 10, y 10"),
        "{stdout}"
    );
    assert!(
        stdout.contains("raster (0, 0, 0) = map (2667400, 6478710, 0), pixel is area"),
        "{stdout}"
    );
    assert!(stdout.contains("nodata (tag 42113): -9999"), "{stdout}");
    assert!(stdout.contains("filled: 14 nodata cells"), "{stdout}");
    // --grid-size resamples it.
    let out = paretomesh(&["info", tif.to_str().unwrap(), "--grid-size", "44x31"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("size: 44×31"));
    // An unsupported codec is named.
    let jpeg = data("bunny_33x33_jpeg.tif");
    let out = paretomesh(&["info", jpeg.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("JPEG"), "{}", text(&out.stderr));
}

/// A closed tube shell along z as OBJ text: an outer wall of radius 1, an inner wall of 0.95,
/// joined by flat rings at both ends.
fn thick_tube_obj() -> String {
    let (angles, rows) = (48usize, 17usize);
    let mut obj = String::new();
    for radius in [1.0f64, 0.95] {
        for r in 0..rows {
            for a in 0..angles {
                let theta = std::f64::consts::TAU * a as f64 / angles as f64;
                let z = -2.0 + 4.0 * r as f64 / (rows - 1) as f64;
                obj.push_str(&format!(
                    "v {} {} {z}\n",
                    radius * theta.cos(),
                    radius * theta.sin()
                ));
            }
        }
    }
    // OBJ indices start at 1.
    let at = |wall: usize, r: usize, a: usize| wall * rows * angles + r * angles + a % angles + 1;
    for a in 0..angles {
        for r in 0..rows - 1 {
            for wall in 0..2 {
                let (p, q, s, t) = (
                    at(wall, r, a),
                    at(wall, r, a + 1),
                    at(wall, r + 1, a + 1),
                    at(wall, r + 1, a),
                );
                obj.push_str(&format!("f {p} {q} {s}\nf {p} {s} {t}\n"));
            }
        }
        for r in [0, rows - 1] {
            let (o0, o1, i0, i1) = (at(0, r, a), at(0, r, a + 1), at(1, r, a), at(1, r, a + 1));
            obj.push_str(&format!("f {o0} {o1} {i1}\nf {o0} {i1} {i0}\n"));
        }
    }
    obj
}

#[test]
fn a_closed_thick_mesh_needs_surface_outer() {
    let dir = scratch("thick");
    let path = dir.join("tube.obj");
    std::fs::write(&path, thick_tube_obj()).unwrap();
    let file = path.to_str().unwrap();
    let out = paretomesh(&["info", file]);
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(stderr.contains("folds over itself"), "{stderr}");
    assert!(stderr.contains("--surface outer"), "{stderr}");
    let out = paretomesh(&["info", file, "--surface", "outer", "--grid-size", "64x32"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("placement: cylindrical unwrap"), "{stdout}");
    assert!(stdout.contains("outer surface: "), "{stdout}");
    // The outer wall's radius is 1 (chords of 48 segments sag by under 0.3 %).
    let range = stdout
        .lines()
        .find_map(|l| l.strip_prefix("z range: "))
        .unwrap();
    let (lo, hi) = range.split_once(" .. ").unwrap();
    let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
    assert!(lo > 0.99 && hi <= 1.0 + 1e-9, "{range}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn greedy_stops_at_a_vertical_error_in_the_surfaces_units() {
    // Like hmm's -e: insertion stops at the first mesh whose largest vertical error is at most
    // X, so that mesh (the front's last) is within X, and so is its bounded-error decimation,
    // with fewer triangles; every other member is not.
    let out = scratch("vertical").join("front.json");
    let grid = data("volcano_33x33.f32");
    let x = 4.0;
    let run = paretomesh(&[
        "run",
        grid.to_str().unwrap(),
        "--algo",
        "greedy",
        "--max-vertical-error",
        &x.to_string(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let file: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let front = file["front"].as_array().unwrap();
    let e_max: Vec<f64> = front.iter().map(|m| m["E_max"].as_f64().unwrap()).collect();
    // The front is in E_max: the members within X are the last one or two, the decimated
    // mesh first (greedy's own stop mesh stays only where its E_max is lower).
    let within: Vec<usize> = (0..e_max.len()).filter(|&k| e_max[k] <= x).collect();
    assert!(
        !within.is_empty() && within.len() <= 2 && *within.last().unwrap() == e_max.len() - 1,
        "{e_max:?}"
    );
    let t = |k: usize| front[k]["T"].as_u64().unwrap();
    assert!(within.iter().all(|&k| t(k) >= t(within[0])));
    assert_eq!(file["params"]["decimate"], true);
    assert_eq!(file["params"]["error"], "max");
    assert!(front.last().unwrap()["T"].as_u64().unwrap() < 2 * 32 * 32);

    // One stop at a time, and only for greedy insertion.
    for (extra, expected) in [
        (
            vec![
                "--algo",
                "greedy",
                "--max-vertical-error",
                "1",
                "--evals",
                "9",
            ],
            "not several",
        ),
        (
            vec!["--algo", "nsga2", "--max-vertical-error", "1"],
            "--max-vertical-error does not apply to --algo nsga2",
        ),
    ] {
        let mut args = vec![
            "run",
            grid.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let refused = paretomesh(&args);
        assert_eq!(refused.status.code(), Some(1));
        assert!(
            text(&refused.stderr).contains(expected),
            "{}",
            text(&refused.stderr)
        );
    }
}

/// Ctrl-C in the middle of a run: front.json is written to a hidden file and renamed into place
/// only once complete, so the output path must not exist after an interrupted run.
#[cfg(unix)]
#[test]
fn an_interrupted_run_leaves_no_front_json() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Command;
    let dir = scratch("interrupted");
    let out = dir.join("front.json");
    let grid = data("jacksboro_65x65.f32");
    // A budget no machine finishes in the second before the interrupt.
    let mut child = Command::new(env!("CARGO_BIN_EXE_paretomesh"))
        .args(["run", grid.to_str().unwrap(), "--evals", "1000000000"])
        .arg("--out")
        .arg(&out)
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("the paretomesh binary runs");
    std::thread::sleep(std::time::Duration::from_secs(1));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    let status = child.wait().unwrap();
    assert_eq!(
        status.signal(),
        Some(2),
        "the run ended by itself: {status:?}"
    );
    assert!(!out.exists(), "an interrupted run left {}", out.display());
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "an interrupted run left files: {left:?}");
}
