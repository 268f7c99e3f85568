//! `paretomesh run --algo greedy|decimation`: the fronts it writes rescore (the methods
//! themselves are tested in `src/baselines/tests.rs`).

use paretomesh::evaluator::Evaluator;
use paretomesh::front::Solution;
use paretomesh::front_file::FrontFile;
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use std::path::Path;
use std::sync::Arc;

mod common;
use common::cli::data;

fn fixture(name: &str) -> Arc<Heightfield> {
    Arc::new(import::load(&data(&format!("{name}.f32"))).unwrap())
}

#[test]
fn cli_run_greedy_and_decimation_write_fronts_that_rescore() {
    // `paretomesh run --algo greedy|decimation` must write a front.json naming the algorithm,
    // whose every solution re-scores to its stated numbers; greedy's --max-error-fraction stop
    // must hold on its last (largest-T) solution or on one before it.
    let exe = env!("CARGO_BIN_EXE_paretomesh");
    let grid = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/volcano_33x33.f32");
    let hf = fixture("volcano_33x33");
    let (lo, hi) = hf.z_range();
    let runs: [(&str, &[&str]); 3] = [
        ("greedy", &["--max-error-fraction", "0.01"]),
        ("greedy", &["--rule", "sum-reduction", "--evals", "50"]),
        ("decimation", &[]),
    ];
    for (k, (algo, extra)) in runs.into_iter().enumerate() {
        let out = std::env::temp_dir().join(format!(
            "paretomesh_baselines_cli_{k}_{}.json",
            std::process::id()
        ));
        let output = std::process::Command::new(exe)
            .arg("run")
            .arg(&grid)
            .args(["--algo", algo, "--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let file: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
        std::fs::remove_file(&out).unwrap();
        assert_eq!(file["algorithm"], algo);
        let run: FrontFile = serde_json::from_value(file.clone()).unwrap();
        let front: Vec<Solution> = run.front.into_iter().map(|m| m.solution).collect();
        assert!(!front.is_empty());
        let mut ev = Evaluator::new(hf.clone());
        for s in &front {
            let score = ev.score(&s.kept).unwrap();
            assert_eq!((score.e_sum, score.e_max, score.t), (s.e_sum, s.e_max, s.t));
        }
        match k {
            0 => assert!(front.iter().any(|s| s.e_max <= 0.01 * (hi - lo))),
            1 => assert_eq!(file["evaluations"], 50),
            _ => assert!(front.len() <= 10),
        }
    }
    // Decimation has no evaluation budget: asking for one is an error, not a silent no-op.
    let refused = std::process::Command::new(exe)
        .arg("run")
        .arg(&grid)
        .args(["--algo", "decimation", "--evals", "5", "--out"])
        .arg(std::env::temp_dir().join("paretomesh_never_written.json"))
        .output()
        .unwrap();
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--evals"));
}
