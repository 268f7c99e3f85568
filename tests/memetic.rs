//! The memetic NSGA-II: every operator keeps the corners and gives the score a fresh
//! evaluation gives; a seed reproduces a run however it is sliced; the front weakly dominates
//! the greedy fronts it was seeded from.
//!
//! Grids are small (33×33) and budgets low because the tests run in a debug build.

mod common;

use common::{bits, fixture, random_kept, synthetic};
use paretomesh::baselines::{GreedyInsertion, GreedyParams, InsertionRule};
use paretomesh::evaluator::{Evaluator, Score};
use paretomesh::evolution::memetic::decimation::Decimation;
use paretomesh::evolution::memetic::local_search::LocalSearch;
use paretomesh::evolution::memetic::member::Member;
use paretomesh::evolution::memetic::mutation;
use paretomesh::evolution::memetic::neighbour_mating::{self, Cut};
use paretomesh::evolution::memetic::seeding::densest_seed;
use paretomesh::evolution::memetic::seeding_budget;
use paretomesh::evolution::{Memetic, MemeticParams};
use paretomesh::front::{Front, dominates};
use paretomesh::heightfield::Heightfield;
use paretomesh::optimizer::Optimizer;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;

/// Members of a greedy run's front, as members with meshes.
fn greedy_members(hf: &Arc<Heightfield>, ev: &mut Evaluator) -> Vec<Member> {
    let mut run = GreedyInsertion::new(hf.clone(), GreedyParams::default()).unwrap();
    run.run_to_end();
    run.front()
        .solutions()
        .iter()
        .filter(|s| s.t >= 8)
        .map(|s| Member::fresh(ev, s.kept.clone()))
        .collect()
}

/// `member`'s score is a fresh evaluation's, bit for bit, and it keeps the corners.
fn check(ev: &mut Evaluator, hf: &Heightfield, member: &Member, what: &str) {
    check_kept(ev, hf, &member.kept, member.score, what);
}

/// [`check`] for a kept set and the score it was given.
fn check_kept(ev: &mut Evaluator, hf: &Heightfield, kept: &[u32], score: Score, what: &str) {
    for c in hf.corners() {
        assert!(kept.binary_search(&c).is_ok(), "{what}: corner {c} lost");
    }
    assert!(kept.is_sorted(), "{what}: kept list out of order");
    let fresh = ev.score(kept).unwrap();
    assert_eq!(bits(score), bits(fresh), "{what}");
}

#[test]
fn every_operator_keeps_the_corners_and_scores_as_a_fresh_evaluation() {
    for hf in [fixture("camera_33x33"), synthetic(21, 17, 2)] {
        let mut ev = Evaluator::new(hf.clone());
        let mut rng = Pcg64Mcg::seed_from_u64(5);
        let mut members = greedy_members(&hf, &mut ev);
        // And an unstructured kept set, far from anything greedy makes.
        let mut kept = random_kept(hf.len(), 0.2, &mut rng);
        kept.extend(hf.corners());
        kept.sort_unstable();
        kept.dedup();
        members.push(Member::fresh(&mut ev, kept));
        assert!(members.len() >= 4);
        let mut applied = [0usize; 4];
        for round in 0..40 {
            let k = round % members.len();
            let mut child = members[k].clone();
            child.guide(&hf);
            let guide = child.guide.clone().unwrap();
            if let Some(edit) = mutation::insert(&hf, &guide, &mut rng) {
                assert_eq!(edit.insert.len(), 1);
                let before = child.score.t;
                child.apply(&mut ev, &edit);
                check(&mut ev, &hf, &child, "guided insertion");
                assert!(child.score.t > before);
                applied[0] += 1;
            }
            let mut child = members[k].clone();
            child.guide(&hf);
            let guide = child.guide.clone().unwrap();
            if let Some(edit) = mutation::remove(&guide, &mut rng) {
                assert!(!hf.corners().contains(&edit.remove[0]));
                child.apply(&mut ev, &edit);
                check(&mut ev, &hf, &child, "guided removal");
                applied[1] += 1;
            }
            let mut child = members[k].clone();
            child.guide(&hf);
            child.ready_for_trials();
            let mut evaluations = 0;
            if let Some((edit, score)) =
                mutation::best_move(&mut ev, &child, &mut rng, &mut evaluations)
            {
                assert!(evaluations >= 1);
                let t = child.score.t;
                child.apply(&mut ev, &edit);
                check(&mut ev, &hf, &child, "vertex move");
                assert_eq!(
                    bits(child.score),
                    bits(score),
                    "a move's trial is its score"
                );
                assert_eq!(child.score.t, t, "a move keeps T");
                applied[2] += 1;
            }
            let mate = neighbour_mating::pick_mate(&members, k, &mut rng).unwrap();
            let cut = Cut::draw(&hf, &mut rng);
            let (lo, hi) = members.split_at_mut(k.max(mate));
            let (a, b) = if k < mate {
                (&mut lo[k], &mut hi[0])
            } else {
                (&mut hi[0], &mut lo[mate])
            };
            let child = neighbour_mating::cross(&mut ev, a, b, cut);
            check(&mut ev, &hf, &child, "crossover");
            for &i in &child.kept {
                let from = if cut.from_second(&hf, i) {
                    &b.kept
                } else {
                    &a.kept
                };
                assert!(
                    from.binary_search(&i).is_ok() || hf.corners().contains(&i),
                    "crossover: point {i} comes from neither side"
                );
            }
            applied[3] += 1;
        }
        assert!(
            applied.iter().all(|&n| n > 10),
            "operators applied: {applied:?}"
        );
    }
}

#[test]
fn local_search_keeps_the_corners_scores_honestly_and_improves_at_fixed_t() {
    let hf = fixture("camera_33x33");
    let mut ev = Evaluator::new(hf.clone());
    let mut run = GreedyInsertion::new(hf.clone(), GreedyParams::default()).unwrap();
    run.run_to_end();
    let greedy = run.front().clone();
    let mut archive = greedy.clone();
    let mut local = LocalSearch::new(&hf);
    let mut rng = Pcg64Mcg::seed_from_u64(3);
    let mut evaluations = 0;
    for _ in 0..300 {
        local.unit(&mut ev, &mut archive, &mut rng, &mut evaluations);
    }
    assert!(evaluations > 300);
    for s in archive.solutions() {
        for c in hf.corners() {
            assert!(s.kept.contains(&c));
        }
        let fresh = ev.score(&s.kept).unwrap();
        assert_eq!((s.e_sum.to_bits(), s.t), (fresh.e_sum.to_bits(), fresh.t));
    }
    // Some greedy member was beaten at its own T or below.
    let improved = greedy.solutions().iter().any(|g| {
        archive
            .solutions()
            .iter()
            .any(|m| m.t <= g.t && m.e_sum < g.e_sum)
    });
    assert!(improved, "local search improved no greedy member");
}

#[test]
fn the_worst_triangle_rule_inserts_the_worst_point_of_the_largest_error_sum() {
    let hf = fixture("camera_33x33");
    let params = GreedyParams {
        rule: InsertionRule::WorstTriangle,
        ..GreedyParams::default()
    };
    let mut run = GreedyInsertion::new(hf.clone(), params).unwrap();
    let mut ev = Evaluator::new(hf.clone());
    for _ in 0..60 {
        let kept = run.kept();
        let mut m = Member::fresh(&mut ev, kept.clone());
        let guide = m.guide(&hf).clone();
        let t = guide.largest_triangles(1)[0];
        let expected = guide.worst_point(&hf, t);
        run.step(1);
        let now = run.kept();
        let added: Vec<u32> = now.iter().copied().filter(|i| !kept.contains(i)).collect();
        assert_eq!(added, vec![expected]);
    }
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
fn members_between_uses_hold_no_per_grid_point_arrays_and_seeds_stay_below_the_densest_seed() {
    // A stowed member's mesh lends its per-grid-point arrays to the members being edited, so
    // the population's memory grows with its meshes, not with the grid; the seeds are at most
    // the densest seed (a quarter of the full mesh on this grid).
    let hf = fixture("volcano_33x33");
    let mut run = Memetic::new(hf.clone(), params(seeding_budget(&hf) + 2000), 3).unwrap();
    let (mut checked, mut seeds_seen) = (0, false);
    // Slices of one unit, so that the population is seen as soon as the last seed joins.
    while !run.step(1).done {
        if !seeds_seen && run.population().len() == 8 {
            assert_eq!(densest_seed(&hf), hf.full_triangles() / 4);
            let densest = densest_seed(&hf);
            assert!(run.population().iter().all(|m| m.score.t <= densest));
            seeds_seen = true;
        }
        for m in run.population() {
            assert!(!m.state.has_lookups(), "a population member is stowed");
            // Its score is still its mesh's, and its mesh can be lent arrays again.
            assert_eq!(m.state.score(), Some(m.score));
            checked += 1;
        }
    }
    assert!(seeds_seen && checked > 100, "the run got past seeding");
    let mut member = run.population()[0].clone();
    let mut pool = paretomesh::evolution::memetic::member::LookupPool::default();
    member.unstow(&mut pool);
    assert!(member.state.has_lookups());
    let mut ev = Evaluator::new(hf.clone());
    let edit = paretomesh::evolution::memetic::member::Edit {
        remove: Vec::new(),
        insert: (0..hf.len() as u32)
            .filter(|i| member.kept.binary_search(i).is_err())
            .take(3)
            .collect(),
    };
    member.apply(&mut ev, &edit);
    check(&mut ev, &hf, &member, "an edit of an unstowed member");
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

#[test]
fn decimation_removes_the_cheapest_vertex_per_triangle_saved_and_records_honest_meshes() {
    // Brute force: before each removal every other vertex's removal is scored from scratch,
    // and the decimation must take one of least rise of E_sum per triangle saved (border
    // vertices save one triangle, interior ones two).
    let hf = fixture("volcano_33x33");
    let mut rng = Pcg64Mcg::seed_from_u64(4);
    let mut start = random_kept(hf.len(), 0.08, &mut rng);
    start.extend(hf.corners());
    start.sort_unstable();
    start.dedup();
    let mut ev = Evaluator::new(hf.clone());
    let mut fresh_ev = Evaluator::new(hf.clone());
    let mut run = Decimation::new(&mut ev, start.clone());
    let corners = hf.corners();
    assert!(start.len() > 60, "a start with room to choose");
    let mut records: Vec<(Vec<u32>, Score)> = Vec::new();
    let mut removals = 0;
    while !run.is_done() {
        let before = run.member().kept.clone();
        let score = run.member().score;
        let cost = |ev: &mut Evaluator, v: u32| {
            let kept: Vec<u32> = before.iter().copied().filter(|&u| u != v).collect();
            let after = ev.score(&kept).unwrap();
            (after.e_sum - score.e_sum) / (score.t - after.t) as f64
        };
        run.unit(&mut ev, |kept, score| records.push((kept.to_vec(), *score)));
        let after = &run.member().kept;
        if after.len() == before.len() {
            continue;
        }
        let removed: Vec<u32> = before
            .iter()
            .copied()
            .filter(|v| !after.contains(v))
            .collect();
        assert_eq!(removed.len(), 1, "one vertex per removal");
        let least = (before.iter().copied())
            .filter(|v| !corners.contains(v))
            .map(|v| cost(&mut fresh_ev, v))
            .fold(f64::INFINITY, f64::min);
        assert_eq!(cost(&mut fresh_ev, removed[0]), least, "removal {removals}");
        removals += 1;
    }
    assert_eq!(removals, start.len() - 4, "down to the corners");
    // Every recording is honest and keeps the corners. Each is the first mesh at or below 98 %
    // of the T before it (at least one triangle less), so no gap is wider than 2 % plus the
    // one removal (of one or two triangles) that crossed the mark.
    assert_eq!(records[0].0, start);
    assert_eq!(records.last().unwrap().1.t, 2);
    for pair in records.windows(2) {
        let (before, t) = (pair[0].1.t, pair[1].1.t);
        let mark = ((before as f64 * 0.98) as usize).min(before - 1);
        assert!(t <= mark && t + 1 >= mark, "{before} then {t}");
    }
    for (k, (kept, score)) in records.iter().enumerate() {
        check_kept(&mut fresh_ev, &hf, kept, *score, &format!("recording {k}"));
    }
}
