//! The memetic method's operators, each on its own: every one keeps the corners and gives the
//! score a fresh evaluation gives; the local search improves at fixed T; stowed members hold no
//! per-grid-point arrays; the decimation removes the cheapest vertex. The whole method, through
//! its public API and the CLI, is tested in `tests/memetic.rs`.
//!
//! Grids are small (33×33) and budgets low because the tests run in a debug build.

use super::decimation::Decimation;
use super::local_search::LocalSearch;
use super::member::{Edit, LookupPool, Member};
use super::mutation;
use super::neighbour_mating::{self, Cut};
use super::seeding::densest_seed;
use super::{Memetic, MemeticParams, seeding_budget};
use crate::baselines::{GreedyInsertion, GreedyParams, InsertionRule};
use crate::evaluator::{Evaluator, Score};
use crate::heightfield::Heightfield;
use crate::import;
use crate::optimizer::Optimizer;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::path::Path;
use std::sync::Arc;

/// The fixture `tests/data/{name}.f32`.
fn fixture(name: &str) -> Arc<Heightfield> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(format!("{name}.f32"));
    Arc::new(import::load(&path).expect("fixture"))
}

/// A grid of integer-valued heights (many exact ties in the interpolation).
fn synthetic(width: usize, height: usize, seed: u64) -> Arc<Heightfield> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let z = (0..width * height)
        .map(|_| rng.random_range(0..5) as f64)
        .collect();
    Arc::new(Heightfield::new(width, height, z).unwrap())
}

/// A score as exact bits, to compare with `assert_eq!`.
fn bits(s: Score) -> (u64, u64, u64, usize) {
    (s.e_sum.to_bits(), s.e_max.to_bits(), s.rms.to_bits(), s.t)
}

/// Each of the `n` grid points with probability `density`.
fn random_kept(n: usize, density: f64, rng: &mut Pcg64Mcg) -> Vec<u32> {
    (0..n as u32)
        .filter(|_| rng.random::<f64>() < density)
        .collect()
}

fn params(evals: u64) -> MemeticParams {
    MemeticParams {
        population: 8,
        local_search_rounds: 6,
        max_evaluations: Some(evals),
        ..MemeticParams::default()
    }
}

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
            if let Some((edit, score)) = mutation::best_move(
                &mut ev,
                &child,
                crate::measure::ErrorMeasure::Sum,
                &mut rng,
                &mut evaluations,
            ) {
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
                let from = if cut.is_from_second(&hf, i) {
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
    let mut pool = LookupPool::default();
    member.unstow(&mut pool);
    assert!(member.state.has_lookups());
    let mut ev = Evaluator::new(hf.clone());
    let edit = Edit {
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
    let mut run = Decimation::new(&mut ev, start.clone(), crate::measure::ErrorMeasure::Sum);
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
