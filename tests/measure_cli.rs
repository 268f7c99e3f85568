//! `paretomesh run --error sum|rms|max`: fronts Pareto-optimal in the chosen error, every
//! member's three errors exact, the measure on file, and refusals that name what was asked.

use paretomesh::evaluator::Evaluator;
use paretomesh::front::dominates;
use paretomesh::front_file::FrontFile;
use paretomesh::import;
use paretomesh::measure::ErrorMeasure;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Arc;

const GRID: &str = "tests/data/volcano_33x33.f32";

fn paretomesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_paretomesh"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .expect("the paretomesh binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("paretomesh-measure-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs `run` with `more` options, expecting success, and reads its front.json.
fn run(out: &Path, more: &[&str]) -> (FrontFile, String) {
    let mut args = vec!["run", GRID, "--seed", "3", "--out", s(out)];
    args.extend_from_slice(more);
    let result = paretomesh(&args);
    assert!(
        result.status.success(),
        "{args:?}: {}",
        text(&result.stderr)
    );
    let json = std::fs::read_to_string(out).unwrap();
    (serde_json::from_str(&json).unwrap(), json)
}

#[test]
fn each_measure_gives_a_front_pareto_optimal_in_it_with_exact_errors() {
    let dir = scratch("fronts");
    let hf =
        Arc::new(import::load(Path::new(env!("CARGO_MANIFEST_DIR")).join(GRID).as_path()).unwrap());
    let mut ev = Evaluator::new(hf);
    for algo in ["greedy", "decimation", "memetic"] {
        for measure in ErrorMeasure::ALL {
            let out = dir.join(format!("{algo}-{measure}.json"));
            let mut more = vec!["--algo", algo, "--error", measure.name()];
            if algo == "memetic" {
                more.extend_from_slice(&["--evals", "3000"]);
            }
            let (file, json) = run(&out, &more);
            assert_eq!(file.measure().unwrap(), measure);
            // A sum front's file is as it was: no measure, no RMS.
            assert_eq!(
                json.contains("\"error\""),
                measure != ErrorMeasure::Sum,
                "{algo}"
            );
            assert_eq!(
                json.contains("\"RMS\""),
                measure != ErrorMeasure::Sum,
                "{algo}"
            );
            assert!(!file.front.is_empty());
            for (i, m) in file.front.iter().enumerate() {
                let fresh = ev.score(&m.solution.kept).unwrap();
                let s = &m.solution;
                assert_eq!((s.e_sum, s.e_max, s.t), (fresh.e_sum, fresh.e_max, fresh.t));
                if measure != ErrorMeasure::Sum {
                    assert_eq!(s.rms, fresh.rms, "{algo} {measure} member {i}");
                }
                for o in &file.front[..i] {
                    let (a, b) = (
                        [measure.of(&fresh), s.t as f64],
                        [
                            measure.of(&ev.score(&o.solution.kept).unwrap()),
                            o.solution.t as f64,
                        ],
                    );
                    assert!(!dominates(a, b) && !dominates(b, a), "{algo} {measure}");
                }
            }
        }
    }
}

#[test]
fn the_default_measure_is_sum_and_leaves_the_file_as_it_was() {
    let dir = scratch("default");
    let blank = |json: &str| {
        let mut v: serde_json::Value = serde_json::from_str(json).unwrap();
        v["millis"] = 0.into();
        v
    };
    for algo in ["nsga2", "greedy"] {
        let mut plain = vec!["--algo", algo];
        if algo == "nsga2" {
            plain.extend_from_slice(&["--gens", "2"]);
        }
        let mut sum = plain.clone();
        sum.extend_from_slice(&["--error", "sum"]);
        let (_, a) = run(&dir.join("plain.json"), &plain);
        let (_, b) = run(&dir.join("sum.json"), &sum);
        assert_eq!(blank(&a), blank(&b), "{algo}");
    }
}

#[test]
fn bad_measures_are_refused_with_a_message_and_no_file() {
    let dir = scratch("bad");
    let out = dir.join("front.json");
    let refused = |args: &[&str]| {
        let result = paretomesh(args);
        let stderr = text(&result.stderr);
        assert!(!result.status.success(), "{args:?}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(!out.exists(), "{args:?} left a file");
        stderr
    };
    let e = refused(&["run", GRID, "--error", "mean", "--out", s(&out)]);
    assert!(
        e.contains("'mean'") && e.contains("--error") && e.contains("sum, rms, max"),
        "{e}"
    );
    for (algo, measure) in [("nsga2", "max"), ("nsga2", "rms"), ("weighted", "max")] {
        let e = refused(&[
            "run",
            GRID,
            "--algo",
            algo,
            "--error",
            measure,
            "--out",
            s(&out),
        ]);
        assert!(
            e.contains(&format!("--algo {algo} does not take --error {measure}")),
            "{e}"
        );
    }
}
