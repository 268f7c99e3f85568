//! The real `paretomesh` binary on fixtures and on bad files: output, exit status, messages.

use std::path::PathBuf;
use std::process::{Command, Output};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn paretomesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_paretomesh"))
        .args(args)
        .output()
        .expect("the paretomesh binary runs")
}

/// A scratch directory for this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("paretomesh-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

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
