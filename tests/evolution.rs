//! `paretomesh run` with the GAs on real terrain: the front.json it writes rescores exactly, and
//! bad parameters get a message (the GAs themselves are tested in `src/evolution/tests.rs`).

use paretomesh::evaluator::{Evaluator, canonical_set};
use paretomesh::front_file::FrontFile;
use paretomesh::import;
use std::sync::Arc;

mod common;
use common::cli::{data, paretomesh};

#[test]
fn cli_run_writes_a_front_json_that_rescores_identically() {
    let dir = std::env::temp_dir().join(format!("paretomesh-evolution-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let grid = data("jacksboro_33x33.f32");
    let hf = Arc::new(import::load(&grid).unwrap());
    for algo in ["nsga2", "weighted"] {
        let out = dir.join(format!("{algo}.json"));
        let csv = dir.join(format!("{algo}.csv"));
        // NSGA-II's file lists triangles (`--triangles`), the weighted-sum GA's kept sets only.
        let mut args = vec![
            "run",
            grid.to_str().unwrap(),
            "--algo",
            algo,
            "--pop",
            "6",
            "--gens",
            "2",
            "--seed",
            "3",
            "--out",
            out.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
        ];
        if algo == "nsga2" {
            args.push("--triangles");
        }
        let run = paretomesh(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{stderr}");
        assert!(
            stderr.contains("evaluations"),
            "progress on stderr: {stderr}"
        );
        let file: FrontFile =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let run = &file.header;
        assert_eq!((run.grid.width, run.grid.height), (33, 33));
        assert_eq!((run.algorithm.name(), run.seed), (algo, 3));
        assert_eq!(run.params["population"], 6);
        assert!(run.evaluations > 0);
        let mut ev = Evaluator::new(hf.clone());
        for s in &file.front {
            let fresh = ev.evaluate(&s.solution.kept).unwrap();
            assert_eq!(fresh.score.e_sum, s.solution.e_sum);
            assert_eq!(fresh.score.e_max, s.solution.e_max);
            assert_eq!(fresh.score.t, s.solution.t);
            let Some(triangles) = &s.triangles else {
                assert_eq!(
                    algo, "weighted",
                    "only NSGA-II's file was asked for triangles"
                );
                continue;
            };
            assert_eq!(algo, "nsga2");
            // Listed in canonical order (each rotated to its smallest index, then sorted).
            assert_eq!(&canonical_set(&fresh.triangles), triangles);
            // An outside tool scoring the triangles alone gets the same error.
            let outside = ev.score_triangulation(triangles).unwrap();
            assert!((outside.e_sum - s.solution.e_sum).abs() <= 1e-9 * s.solution.e_sum.max(1.0));
        }
        let rows: Vec<String> = std::fs::read_to_string(&csv)
            .unwrap()
            .lines()
            .map(String::from)
            .collect();
        assert_eq!(rows[0], "T,E_sum,E_max,kept");
        assert_eq!(rows.len(), file.front.len() + 1);
        let first: Vec<f64> = rows[1].split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(
            first,
            [
                file.front[0].solution.t as f64,
                file.front[0].solution.e_sum,
                file.front[0].solution.e_max,
                file.front[0].solution.kept.len() as f64
            ]
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn cli_run_rejects_bad_parameters_with_a_message() {
    let grid = data("jacksboro_33x33.f32");
    let run = paretomesh(&[
        "run",
        grid.to_str().unwrap(),
        "--algo",
        "nsga2",
        "--pc",
        "3",
        "--out",
        "/nonexistent/never-written.json",
    ]);
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("crossover probability must be between 0 and 1"),
        "{stderr}"
    );
}

#[test]
fn cli_run_rejects_a_bad_greedy_seed_fraction() {
    let grid = data("jacksboro_33x33.f32");
    for (algo, fraction, message) in [
        (
            "nsga2",
            "1.5",
            "greedy seed fraction must be between 0 and 1",
        ),
        ("weighted", "0.1", "offered for NSGA-II only"),
        ("greedy", "0.1", "--greedy-seed applies to NSGA-II only"),
    ] {
        let run = paretomesh(&[
            "run",
            grid.to_str().unwrap(),
            "--algo",
            algo,
            "--greedy-seed",
            fraction,
            "--out",
            "/nonexistent/never-written.json",
        ]);
        assert!(!run.status.success());
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(stderr.contains(message), "{algo}: {stderr}");
    }
}
