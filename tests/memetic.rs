//! The memetic NSGA-II through its public API and the CLI: a seed reproduces a run however it
//! is sliced; the front weakly dominates the greedy fronts it was seeded from; each ablation
//! switch changes the run; bad parameters are refused. Its operators, one by one, are tested
//! inside the crate (`src/evolution/memetic/tests.rs`).
//!
//! Grids are small (33×33) and budgets low because the tests run in a debug build.

use paretomesh::evaluator::Evaluator;
use paretomesh::evolution::memetic::seeding_budget;
use paretomesh::evolution::{Memetic, MemeticParams};
use paretomesh::front::{Front, dominates};
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::optimizer::Optimizer;
use std::path::Path;
use std::sync::Arc;

/// The fixture `tests/data/{name}.f32`.
fn fixture(name: &str) -> Arc<Heightfield> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(format!("{name}.f32"));
    Arc::new(import::load(&path).expect("fixture"))
}

fn params(evals: u64) -> MemeticParams {
    MemeticParams {
        population: 8,
        local_search_rounds: 6,
        max_evaluations: Some(evals),
        ..MemeticParams::default()
    }
}

fn pairs(front: &Front) -> Vec<(u64, usize, Vec<u32>)> {
    front
        .solutions()
        .iter()
        .map(|s| (s.e_sum.to_bits(), s.t, s.kept.clone()))
        .collect()
}

#[test]
fn a_seed_reproduces_the_run_however_it_is_sliced() {
    let hf = fixture("camera_33x33");
    let budget = seeding_budget(&hf) + 5000;
    let mut whole = Memetic::new(hf.clone(), params(budget), 9).unwrap();
    let end = whole.run_to_end();
    assert!(end.generation >= 2, "the run got past seeding: {end:?}");
    let mut again = Memetic::new(hf.clone(), params(budget), 9).unwrap();
    again.run_to_end();
    assert_eq!(pairs(whole.front()), pairs(again.front()));
    for slice in [1, 7, 250] {
        let mut sliced = Memetic::new(hf.clone(), params(budget), 9).unwrap();
        while !sliced.step(slice).done {}
        assert_eq!(sliced.progress(), end, "slices of {slice}");
        assert_eq!(
            pairs(sliced.front()),
            pairs(whole.front()),
            "slices of {slice}"
        );
    }
    let mut other = Memetic::new(hf, params(budget), 10).unwrap();
    other.run_to_end();
    assert_ne!(
        pairs(other.front()),
        pairs(whole.front()),
        "another seed, another run"
    );
}

/// The browser shows the front while the greedy sweeps still run: on a large grid a sweep takes
/// seconds, and a front that appeared only when it ended would leave the plot empty that long.
#[test]
fn the_front_grows_from_the_first_units_of_seeding() {
    let hf = fixture("jacksboro_65x65");
    let mut run = Memetic::new(hf.clone(), MemeticParams::default(), 1).unwrap();
    run.step(20);
    assert!(!run.front().is_empty(), "a front after 20 insertions");
    let early = run.front().len();
    // Still inside the first sweep (one insertion per grid point), with more meshes recorded.
    run.step(hf.len() as u64 / 2);
    assert!(run.progress().evaluations < hf.len() as u64);
    assert!(
        run.front().len() > early,
        "the front grows during the sweep"
    );
    let sparsest = &run.front().solutions()[0];
    assert_eq!(
        sparsest.t, 2,
        "the corners-only mesh is the first recording"
    );
}

#[test]
fn the_front_weakly_dominates_its_greedy_seed_front_and_scores_honestly() {
    let hf = fixture("jacksboro_33x33");
    let mut run = Memetic::new(hf.clone(), params(seeding_budget(&hf) + 3000), 1).unwrap();
    run.run_to_end();
    let seeds = run.seed_front();
    assert!(seeds.len() > 20);
    let front = run.front();
    for g in seeds.solutions() {
        assert!(
            front
                .solutions()
                .iter()
                .any(|m| m.objectives() == g.objectives()
                    || dominates(m.objectives(), g.objectives())),
            "greedy member (E {}, T {}) is not weakly dominated",
            g.e_sum,
            g.t
        );
    }
    // And it is better somewhere.
    assert!(front.solutions().iter().any(|m| {
        seeds
            .solutions()
            .iter()
            .any(|g| dominates(m.objectives(), g.objectives()))
    }));
    let mut ev = Evaluator::new(hf.clone());
    for m in front.solutions() {
        let fresh = ev.score(&m.kept).unwrap();
        assert_eq!((m.e_sum.to_bits(), m.t), (fresh.e_sum.to_bits(), fresh.t));
    }
}

#[test]
fn bad_parameters_are_refused_with_a_reason() {
    let hf = fixture("camera_33x33");
    let small = MemeticParams {
        population: 1,
        ..MemeticParams::default()
    };
    let err = Memetic::new(hf.clone(), small, 1).err().unwrap();
    assert!(err.to_string().contains("at least 2"));
    let p = MemeticParams {
        crossover_probability: 1.5,
        ..MemeticParams::default()
    };
    assert!(
        Memetic::new(hf, p, 1)
            .err()
            .unwrap()
            .to_string()
            .contains("[0, 1]")
    );
}

#[test]
fn a_tiny_grid_runs_to_its_budget() {
    let hf = Arc::new(Heightfield::new(2, 2, vec![0.0, 1.0, 2.0, 3.0]).unwrap());
    let mut run = Memetic::new(hf, params(50), 1).unwrap();
    let p = run.run_to_end();
    assert!(p.done && p.evaluations >= 50);
    assert_eq!(run.front().len(), 1);
}

#[test]
fn run_without_algo_is_memetic_and_its_front_rescores() {
    let grid = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/camera_33x33.f32");
    let out = std::env::temp_dir().join(format!(
        "paretomesh_memetic_cli_{}.json",
        std::process::id()
    ));
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_paretomesh"))
        .arg("run")
        .arg(&grid)
        .args(["--evals", "3000", "--pop", "6", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let bytes = std::fs::read(&out).unwrap();
    std::fs::remove_file(&out).unwrap();
    let file: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(file["algorithm"], "memetic");
    assert_eq!(file["params"]["population"], 6);
    // The members through front.json's reader, which unpacks their kept sets.
    let read: paretomesh::front_file::FrontFile = serde_json::from_slice(&bytes).unwrap();
    let hf = fixture("camera_33x33");
    let mut ev = Evaluator::new(hf);
    assert!(read.front.len() > 10);
    for m in &read.front {
        let fresh = ev.score(&m.solution.kept).unwrap();
        assert_eq!(m.solution.e_sum.to_bits(), fresh.e_sum.to_bits());
        assert_eq!(m.solution.t, fresh.t);
    }
    // A GA option that memetic does not take is refused.
    let refused = std::process::Command::new(env!("CARGO_BIN_EXE_paretomesh"))
        .arg("run")
        .arg(&grid)
        .args(["--greedy-seed", "0.5", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("memetic"));
}

#[test]
fn each_ablation_switch_changes_the_run_and_keeps_it_reproducible_and_honest() {
    let hf = fixture("camera_33x33");
    let budget = seeding_budget(&hf) + 5000;
    let mut full = Memetic::new(hf.clone(), params(budget), 4).unwrap();
    full.run_to_end();
    let corners = hf.corners();
    let mut ev = Evaluator::new(hf.clone());
    type Switch = fn(&mut MemeticParams);
    let switches: [(&str, Switch); 4] = [
        ("no greedy seeding", |p| p.greedy_seeding = false),
        ("random mutation", |p| p.guided_mutation = false),
        ("random mates", |p| p.neighbour_mating = false),
        ("no local search", |p| p.local_search = false),
    ];
    for (what, switch) in switches {
        let mut p = params(budget);
        switch(&mut p);
        let mut whole = Memetic::new(hf.clone(), p.clone(), 4).unwrap();
        let end = whole.run_to_end();
        assert!(end.evaluations >= budget, "{what}: {end:?}");
        assert_ne!(pairs(whole.front()), pairs(full.front()), "{what}");
        let mut sliced = Memetic::new(hf.clone(), p.clone(), 4).unwrap();
        while !sliced.step(97).done {}
        assert_eq!(pairs(sliced.front()), pairs(whole.front()), "{what}");
        for s in whole.front().solutions() {
            assert!(
                corners.iter().all(|c| s.kept.binary_search(c).is_ok()),
                "{what}"
            );
            let fresh = ev.score(&s.kept).unwrap();
            assert_eq!((fresh.t, fresh.e_sum), (s.t, s.e_sum), "{what}");
        }
        if !p.greedy_seeding {
            assert!(whole.seed_front().is_empty(), "{what}: no greedy sweep ran");
        }
    }
    // The switches are written only when off, so the full method's parameters read as before.
    let json = serde_json::to_value(MemeticParams::default()).unwrap();
    assert_eq!(json.as_object().unwrap().len(), 4, "{json}");
    let back: MemeticParams = serde_json::from_value(json).unwrap();
    assert_eq!(back, MemeticParams::default());
}

#[test]
fn run_honours_the_population_and_crossover_probability_and_refuses_what_it_would_ignore() {
    let grid = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/camera_33x33.f32");
    let out = std::env::temp_dir().join(format!(
        "paretomesh_memetic_options_{}.json",
        std::process::id()
    ));
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_paretomesh"))
            .arg("run")
            .arg(&grid)
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap()
    };
    let honoured = run(&["--evals", "2500", "--pop", "4", "--pc", "0.6"]);
    assert!(
        honoured.status.success(),
        "{}",
        String::from_utf8_lossy(&honoured.stderr)
    );
    let file: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    std::fs::remove_file(&out).unwrap();
    assert_eq!(file["params"]["population"], 4);
    assert_eq!(file["params"]["crossover_probability"], 0.6);
    // A bad crossover probability is the method's own error.
    let bad = run(&["--pc", "1.5"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("crossover probability"));
    // Each option another method owns is refused by name, with the method, before any run.
    for (algo, option, value) in [
        ("memetic", "--gens", "5"),
        ("memetic", "--pm", "0.01"),
        ("memetic", "--crossover", "uniform"),
        ("memetic", "--factors", "3"),
        ("memetic", "--rule", "worst-triangle"),
        ("memetic", "--max-error-fraction", "0.1"),
        ("nsga2", "--rule", "max-error"),
        ("greedy", "--pop", "10"),
        ("greedy", "--pc", "0.5"),
        ("decimation", "--rule", "max-error"),
    ] {
        let refused = run(&["--algo", algo, option, value]);
        assert!(!refused.status.success(), "{algo} {option}");
        let stderr = String::from_utf8_lossy(&refused.stderr);
        assert!(
            stderr.contains(&format!("{option} does not apply to --algo {algo}")),
            "{algo} {option}: {stderr}"
        );
        assert!(!out.exists(), "{algo} {option}: nothing is written");
    }
    // The --gens refusal says what to use instead.
    let gens = run(&["--gens", "5"]);
    assert!(String::from_utf8_lossy(&gens.stderr).contains("--evals"));
}
