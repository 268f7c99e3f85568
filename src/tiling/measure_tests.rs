//! Tiled runs in `rms` and `max`: the max allocation against brute force, members exact in
//! all three errors and non-dominated in their measure, and the same bits for any thread count.

use super::allocation::{TileOption, allocate_max};
use super::*;
use crate::evaluator::exact::paper_e::brute_force;
use crate::front::dominates;
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;

fn next(state: &mut u64) -> u64 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    *state >> 33
}

/// A rough, deterministic terrain: waves plus hashed noise.
fn terrain(w: usize, h: usize, seed: u64) -> Heightfield {
    let z = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            let mut n = (i as u64 ^ seed).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            n ^= n >> 29;
            (x * 0.21).sin() * 5.0 + (y * 0.13 + x * 0.05).cos() * 3.0 + (n % 1000) as f64 / 1000.0
        })
        .collect();
    Heightfield::new(w, h, z).unwrap()
}

#[test]
fn the_max_allocation_is_the_brute_force_front_in_e_max_and_t() {
    let mut rng = 45u64;
    for _ in 0..300 {
        let tiles = 1 + (next(&mut rng) % 4) as usize;
        let options: Vec<Vec<TileOption>> = (0..tiles)
            .map(|_| {
                let n = 1 + (next(&mut rng) % 6) as usize;
                (0..n)
                    .map(|_| TileOption {
                        e: (next(&mut rng) % 50) as f64,
                        e_max: (next(&mut rng) % 9) as f64,
                        t: 2 + next(&mut rng) % 20,
                    })
                    .collect()
            })
            .collect();
        // Brute force: every combination's (largest E_max, Σ T), then its Pareto front.
        let mut all: Vec<(f64, u64)> = Vec::new();
        let mut choice = vec![0usize; tiles];
        'combinations: loop {
            let e_max = (0..tiles)
                .map(|i| options[i][choice[i]].e_max)
                .fold(0.0, f64::max);
            let t = (0..tiles).map(|i| options[i][choice[i]].t).sum();
            all.push((e_max, t));
            for k in 0..tiles {
                choice[k] += 1;
                if choice[k] < options[k].len() {
                    continue 'combinations;
                }
                choice[k] = 0;
            }
            break;
        }
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
            let e: f64 = a
                .choice
                .iter()
                .enumerate()
                .map(|(i, &c)| options[i][c].e)
                .sum();
            assert_eq!(a.e, e);
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
    let plan = TilePlan::new(hf.width(), hf.height(), 33).unwrap();
    let params = match algorithm {
        "memetic" => serde_json::json!({"max_evaluations": 700, "error": measure.name()}),
        _ => serde_json::json!({"records": 24, "error": measure.name()}),
    };
    let fronts = (0..plan.len())
        .map(|i| run_tile(&plan.cut(hf, i).unwrap(), &plan, i, algorithm, &params, 7).unwrap())
        .collect();
    assemble(&plan, fronts).unwrap()
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
        let runs: Vec<String> = [1, 2, 3]
            .into_iter()
            .map(|threads| {
                let front = run_tiled(&hf, &plan, "memetic", &params, 5, threads).unwrap();
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
