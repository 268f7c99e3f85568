//! Tiled runs in `rms` and `max`: the max allocation against brute force, members exact in
//! all three errors and non-dominated in their measure, and the same bits for any thread count.

use super::allocation::allocate_max;
use super::test_fixtures::{every_choice, random_options, sums, terrain, tiled};
use super::*;
use crate::catalogue::{Algorithm, Config};
use crate::evaluator::exact::paper_e::brute_force;
use crate::front::dominates;
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;

#[test]
fn the_max_allocation_is_the_brute_force_front_in_e_max_and_t() {
    let mut rng = 45u64;
    for _ in 0..300 {
        let options = random_options(&mut rng);
        // Brute force: every combination's (largest E_max, Σ T), then its Pareto front.
        let all: Vec<(f64, u64)> = every_choice(&options)
            .into_iter()
            .map(|(_, e_max, t)| (e_max, t))
            .collect();
        let mut front: Vec<(f64, u64)> = all
            .iter()
            .copied()
            .filter(|&(e, t)| {
                !all.iter()
                    .any(|&(e2, t2)| dominates([e2, t2 as f64], [e, t as f64]))
            })
            .collect();
        front.sort_by(|a, b| a.1.cmp(&b.1).then(a.0.total_cmp(&b.0)));
        front.dedup();
        let found = allocate_max(&options);
        let pairs: Vec<(f64, u64)> = found.iter().map(|a| (a.e_max, a.t)).collect();
        assert_eq!(pairs, front, "{options:?}");
        for a in &found {
            // The sums are those of the options chosen, each within the allocation's E_max.
            assert_eq!(a.e, sums(&options, &a.choice).0);
            assert!(
                a.choice
                    .iter()
                    .enumerate()
                    .all(|(i, &c)| options[i][c].e_max <= a.e_max)
            );
        }
    }
    assert!(allocate_max(&[]).is_empty());
    assert!(allocate_max(&[vec![], vec![]]).is_empty());
}

fn tiled_in(hf: &Heightfield, measure: ErrorMeasure, algorithm: &str) -> TiledFront {
    let params = match algorithm {
        "memetic" => serde_json::json!({"max_evaluations": 700, "error": measure.name()}),
        _ => serde_json::json!({"records": 24, "error": measure.name()}),
    };
    let config = Config::from_json(Algorithm::from_name(algorithm).unwrap(), &params).unwrap();
    tiled(hf, 33, &config)
}

#[test]
fn tiled_members_are_exact_in_all_three_errors_and_non_dominated_in_their_measure() {
    let hf = terrain(70, 50, 4);
    let n = hf.len() as f64;
    for algorithm in ["greedy", "memetic"] {
        for measure in [ErrorMeasure::Rms, ErrorMeasure::Max] {
            let front = tiled_in(&hf, measure, algorithm);
            assert_eq!(front.measure(), measure);
            assert!(front.members.len() > 3, "{algorithm} {measure}");
            let error = |m: &TiledMember| match measure {
                ErrorMeasure::Rms => m.rms.unwrap(),
                _ => m.e_max,
            };
            for (k, m) in front.members.iter().enumerate() {
                let mesh = front.mesh(&hf, k).unwrap();
                assert_eq!(mesh.triangles.len() as u64, m.t);
                let (e_sum, e_max, sq, missing) = brute_force(&hf, &mesh.kept, &mesh.triangles);
                assert_eq!(missing, 0);
                let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(1.0);
                assert!(near(e_sum, m.e_sum), "{algorithm} {measure} {k}: E_sum");
                assert!(near(e_max, m.e_max), "{algorithm} {measure} {k}: E_max");
                let rms = (sq / n).sqrt();
                assert!(near(rms, m.rms.unwrap()), "{algorithm} {measure} {k}: RMS");
                for o in &front.members[..k] {
                    let (a, b) = ([error(m), m.t as f64], [error(o), o.t as f64]);
                    assert!(!dominates(a, b) && !dominates(b, a) && a != b);
                }
            }
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn threads_do_not_change_the_bits_in_any_measure() {
    let hf = terrain(80, 45, 9);
    let plan = TilePlan::new(80, 45, 33).unwrap();
    for measure in ErrorMeasure::ALL {
        let params = serde_json::json!({"max_evaluations": 500, "error": measure.name()});
        let config = Config::from_json(Algorithm::Memetic, &params).unwrap();
        let runs: Vec<String> = [1, 2, 3]
            .into_iter()
            .map(|threads| {
                let front = run_tiled(&hf, &plan, &config, 5, threads).unwrap();
                assert_eq!(front.measure(), measure);
                serde_json::to_string(&front).unwrap()
            })
            .collect();
        assert_eq!(runs[0], runs[1], "{measure}");
        assert_eq!(runs[0], runs[2], "{measure}");
        let read: TiledFront = serde_json::from_str(&runs[0]).unwrap();
        assert_eq!(serde_json::to_string(&read).unwrap(), runs[0]);
    }
}
