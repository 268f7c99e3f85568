//! Greedy insertion and edge decimation on real terrain: their meshes are the evaluator's
//! canonical Delaunay meshes, their recorded numbers are the evaluator's, and they meet their
//! stop contracts (`tests/baselines.rs` runs them through the CLI).

use crate::baselines::{
    DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams, GreedyStop, InsertionRule,
    ParamsError,
};
use crate::evaluator::Evaluator;
use crate::evaluator::canonical_set as canonical;
use crate::evaluator::test_grids::shared_fixture as fixture;
use crate::front::{Front, Solution, dominates};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use std::sync::Arc;

fn assert_rescores(hf: &Arc<Heightfield>, solutions: &[Solution]) {
    let mut ev = Evaluator::new(hf.clone());
    for s in solutions {
        let score = ev.score(&s.kept).unwrap();
        assert_eq!(
            (score.e_sum, score.e_max, score.t),
            (s.e_sum, s.e_max, s.t),
            "a recorded solution with {} points does not re-score identically",
            s.kept.len()
        );
    }
}

fn assert_non_dominated(front: &Front) {
    let s = front.solutions();
    assert!(!s.is_empty());
    for a in s {
        for b in s {
            assert!(!dominates(a.objectives(), b.objectives()));
        }
    }
}

fn greedy(hf: &Arc<Heightfield>, rule: InsertionRule, stop: GreedyStop) -> GreedyInsertion {
    let params = GreedyParams {
        rule,
        stop,
        ..GreedyParams::default()
    };
    GreedyInsertion::new(hf.clone(), params).unwrap()
}

/// A flat `w`×`h` grid with one spike of height 1 at (x, y).
fn single_bump(w: usize, h: usize, x: usize, y: usize) -> Arc<Heightfield> {
    let mut z = vec![0.0; w * h];
    z[y * w + x] = 1.0;
    Arc::new(Heightfield::new(w, h, z).unwrap())
}

#[test]
fn greedy_mesh_is_the_evaluators_canonical_delaunay_as_it_grows() {
    // Real data has many co-circular ties: after every single insertion the incremental mesh
    // must equal the evaluator's triangulation of the same kept set, triangle for triangle.
    for rule in [InsertionRule::MaxError, InsertionRule::SumReduction] {
        let hf = fixture("camera_33x33");
        let mut run = greedy(&hf, rule, GreedyStop::AllPoints);
        let mut ev = Evaluator::new(hf.clone());
        for k in 0..hf.len() {
            // Every state early on, then every 5th (the debug-build evaluator is slow).
            if k > 200 && k % 5 != 0 {
                run.step(1);
                continue;
            }
            let evaluation = ev.evaluate(&run.kept()).unwrap();
            assert_eq!(
                canonical(&run.triangles()),
                canonical(&evaluation.triangles),
                "{rule:?}: mesh differs after {k} insertions"
            );
            // The queue's top is the mesh's true largest error.
            assert_eq!(run.current_max_error(), evaluation.score.e_max);
            let inc = run.incremental_e_sum();
            assert!(
                (inc - evaluation.score.e_sum).abs() <= 1e-9 * evaluation.score.e_sum.max(1.0),
                "{rule:?}: incremental E {inc} vs evaluator {}",
                evaluation.score.e_sum
            );
            if run.step(1).done {
                break;
            }
        }
        assert!(run.progress().done);
    }
}

#[test]
fn greedy_reaches_zero_error_with_every_point() {
    // Running to the end inserts every grid point, so the last solution is the full mesh.
    for name in ["jacksboro_33x33", "volcano_33x33"] {
        let hf = fixture(name);
        for rule in [
            InsertionRule::MaxError,
            InsertionRule::SumReduction,
            InsertionRule::WorstTriangle,
        ] {
            let mut run = greedy(&hf, rule, GreedyStop::AllPoints);
            let p = run.run_to_end();
            assert_eq!(p.evaluations as usize, hf.len() - 4);
            let last = run.recorded().last().unwrap();
            assert_eq!(last.kept.len(), hf.len());
            assert_eq!((last.e_sum, last.e_max), (0.0, 0.0));
            assert_eq!(last.t, hf.full_triangles());
            assert_rescores(&hf, run.recorded());
            assert_non_dominated(run.front());
        }
    }
}

#[test]
fn greedy_on_a_plane_stops_after_the_corners() {
    // A tilted plane is interpolated exactly by the two corner triangles, so the error stop
    // (threshold 0) is met before any insertion.
    let (w, h) = (7, 5);
    let z = (0..w * h)
        .map(|i| 0.5 * (i % w) as f64 - 2.0 * (i / w) as f64 + 3.0)
        .collect();
    let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
    let mut run = greedy(&hf, InsertionRule::MaxError, GreedyStop::MaxError(0.0));
    let p = run.run_to_end();
    assert_eq!(p.evaluations, 0);
    assert_eq!(run.front().len(), 1);
    let s = &run.front().solutions()[0];
    assert_eq!((s.kept.len(), s.t, s.e_max), (4, 2, 0.0));
}

#[test]
fn first_insertion_picks_the_bump() {
    // On a flat 9×7 grid with one spike at (3, 4), the spike is the only point with an error:
    // the classic rule must insert it first.
    let hf = single_bump(9, 7, 3, 4);
    let mut run = greedy(&hf, InsertionRule::MaxError, GreedyStop::Points(5));
    run.run_to_end();
    assert_eq!(run.kept(), vec![0, 8, 4 * 9 + 3, 54, 62]);
    assert_eq!(run.recorded().last().unwrap().t, 4);
}

#[test]
fn sum_reduction_does_not_insert_a_lone_spike() {
    // The same lone spike: inserting it *raises* E_sum (the four fan triangles tilt towards it
    // and err over the whole flat grid), so the E_sum rule must prefer a point that costs
    // nothing, here the first zero-error border point in index order.
    let hf = single_bump(9, 7, 3, 4);
    let mut run = greedy(&hf, InsertionRule::SumReduction, GreedyStop::Points(5));
    run.run_to_end();
    assert!(!run.kept().contains(&(4 * 9 + 3)));
    assert_eq!(run.recorded().last().unwrap().e_sum, 1.0);
}

#[test]
fn both_rules_insert_the_apex_of_a_pyramid_first() {
    // A pyramid over the whole 9×7 grid, zero on the border, apex 1 at (3, 4): the apex has the
    // largest error and inserting it makes the mesh exact, the largest possible reduction.
    let (w, h) = (9usize, 7usize);
    let z = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            (x / 3.0)
                .min((8.0 - x) / 5.0)
                .min(y / 4.0)
                .min((6.0 - y) / 2.0)
        })
        .collect();
    let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
    for rule in [InsertionRule::MaxError, InsertionRule::SumReduction] {
        let mut run = greedy(&hf, rule, GreedyStop::Points(5));
        run.run_to_end();
        assert_eq!(run.kept(), vec![0, 8, 4 * 9 + 3, 54, 62], "{rule:?}");
    }
}

#[test]
fn sum_reduction_prefers_the_broad_feature_over_the_tall_spike() {
    // A pyramid over the whole 9×7 grid (zero on the border, apex 1 at (3, 4)) plus a lone spike
    // of 3 at (7, 1). The spike has the largest vertical error, so the classic rule takes it
    // first; but inserting the apex removes the pyramid's whole error (E drops by Σ pyramid),
    // while inserting the spike tilts big triangles towards it, so the E_sum rule takes the apex.
    let (w, h) = (9usize, 7usize);
    let mut z: Vec<f64> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            (x / 3.0)
                .min((8.0 - x) / 5.0)
                .min(y / 4.0)
                .min((6.0 - y) / 2.0)
        })
        .collect();
    z[w + 7] += 3.0;
    let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
    let mut classic = greedy(&hf, InsertionRule::MaxError, GreedyStop::Points(5));
    classic.run_to_end();
    assert_eq!(classic.kept(), vec![0, 8, 9 + 7, 54, 62]);
    let mut by_sum = greedy(&hf, InsertionRule::SumReduction, GreedyStop::Points(5));
    by_sum.run_to_end();
    assert_eq!(by_sum.kept(), vec![0, 8, 4 * 9 + 3, 54, 62]);
    assert_eq!(by_sum.recorded().last().unwrap().e_sum, 3.0);
}

#[test]
fn greedy_error_stop_meets_its_threshold() {
    // Stopping at 1 % of the z range: the final mesh's E_max is within it, and the mesh one
    // insertion earlier was not (otherwise the run would have stopped there).
    let hf = fixture("jacksboro_65x65");
    let (lo, hi) = hf.z_range();
    let mut run = greedy(
        &hf,
        InsertionRule::MaxError,
        GreedyStop::MaxErrorFraction(0.01),
    );
    let p = run.run_to_end();
    let last = run.recorded().last().unwrap().clone();
    assert!(last.e_max <= 0.01 * (hi - lo));
    assert_eq!(last.kept.len(), 4 + p.evaluations as usize);
    let mut shorter = greedy(
        &hf,
        InsertionRule::MaxError,
        GreedyStop::Points(last.kept.len() - 1),
    );
    shorter.run_to_end();
    let before = shorter.recorded().last().unwrap();
    assert!(before.e_max > 0.01 * (hi - lo));
    assert_rescores(&hf, run.recorded());
    assert_non_dominated(run.front());
}

#[test]
fn greedy_records_a_geometric_sweep() {
    // The default sweep has 64 triangle counts from 2 to the full mesh; rounding merges some
    // small ones, so between 40 and 65 solutions are recorded, with T increasing.
    let hf = fixture("bunny_33x33");
    let mut run = greedy(&hf, InsertionRule::MaxError, GreedyStop::AllPoints);
    run.run_to_end();
    let r = run.recorded();
    assert!((40..=65).contains(&r.len()), "{} records", r.len());
    assert!(r.windows(2).all(|p| p[0].t < p[1].t));
    assert_eq!(r[0].t, 2);
    assert_non_dominated(run.front());
}

#[test]
fn greedy_is_slicing_invariant() {
    // One big step and many one-insertion steps must give the identical front.
    let hf = fixture("volcano_33x33");
    for rule in [InsertionRule::MaxError, InsertionRule::SumReduction] {
        let mut whole = greedy(&hf, rule, GreedyStop::AllPoints);
        whole.run_to_end();
        let mut sliced = greedy(&hf, rule, GreedyStop::AllPoints);
        let mut calls = 0;
        while !sliced.step(7).done {
            calls += 1;
        }
        assert!(calls > 100);
        assert_eq!(whole.front(), sliced.front());
        assert_eq!(whole.recorded(), sliced.recorded());
    }
}

#[test]
fn bad_greedy_params_are_refused() {
    let hf = single_bump(3, 3, 1, 1);
    let bad = GreedyParams {
        stop: GreedyStop::MaxError(f64::NAN),
        ..GreedyParams::default()
    };
    assert!(matches!(
        GreedyInsertion::new(hf.clone(), bad),
        Err(ParamsError::OutOfRange { name: "stop max-error", value, .. }) if value.is_nan()
    ));
    let bad = GreedyParams {
        records: 1,
        ..GreedyParams::default()
    };
    let err = GreedyInsertion::new(hf, bad).err().unwrap();
    assert_eq!(
        err,
        ParamsError::OutOfRange {
            name: "records",
            value: 1.0,
            allowed: "at least 2"
        }
    );
    assert!(err.to_string().contains("records"), "{err}");
}

#[test]
fn decimation_mesh_is_the_evaluators_canonical_delaunay_as_it_shrinks() {
    // Each removal re-triangulates a hole; on real data with co-circular ties the mesh must stay
    // the evaluator's canonical triangulation of the kept set.
    let hf = fixture("bunny_33x33");
    let mut run = EdgeDecimation::new(hf.clone(), DecimationParams::default()).unwrap();
    let mut ev = Evaluator::new(hf.clone());
    let mut steps = 0;
    while !run.progress().done {
        if steps > 200 && steps % 5 != 0 {
            run.step(1);
            steps += 1;
            continue;
        }
        let evaluation = ev.evaluate(&run.kept()).unwrap();
        assert_eq!(
            canonical(&run.triangles()),
            canonical(&evaluation.triangles),
            "mesh differs after {steps} removals"
        );
        assert_eq!(run.triangle_count(), evaluation.score.t);
        run.step(1);
        steps += 1;
    }
    assert!(steps > 100);
}

#[test]
fn decimation_hits_its_reduction_targets() {
    // Contract: the solution for reduction r has ⌊(1 − r)·T_full⌋ − 1 ≤ T ≤ ⌊(1 − r)·T_full⌋.
    for name in ["jacksboro_33x33", "camera_33x33", "volcano_87x61"] {
        let hf = fixture(name);
        let mut run = EdgeDecimation::new(hf.clone(), DecimationParams::default()).unwrap();
        run.run_to_end();
        let full = hf.full_triangles() as f64;
        let recorded = run.recorded();
        assert_eq!(recorded.len(), 10);
        for (r, s) in recorded {
            let bound = ((1.0 - r) * full).floor() as usize;
            assert!(s.t <= bound && s.t + 1 >= bound, "{name}: r {r}, T {}", s.t);
        }
        let solutions: Vec<Solution> = recorded.iter().map(|(_, s)| s.clone()).collect();
        assert_rescores(&hf, &solutions);
        // Flat regions can make several reductions cost nothing (equal E, so the smaller T
        // dominates): the front is the non-dominated subset of the recorded solutions.
        assert!(
            run.front()
                .solutions()
                .iter()
                .all(|f| solutions.contains(f))
        );
        assert_eq!(run.front(), &Front::merged(&solutions));
        assert_non_dominated(run.front());
    }
}

#[test]
fn decimation_removes_the_flat_region_first() {
    // A 5×5 grid flat except a spike at (1, 1): removing any flat point costs nothing, removing
    // the spike costs its height, so the spike survives the first 50 % of reductions.
    let hf = single_bump(5, 5, 1, 1);
    let mut run = EdgeDecimation::new(hf.clone(), DecimationParams::default()).unwrap();
    run.run_to_end();
    for (_, s) in run.recorded() {
        assert!(s.kept.contains(&6));
        assert_eq!(s.e_sum, 0.0);
    }
}

#[test]
fn decimation_is_slicing_invariant() {
    // One big step and many small ones give the identical front.
    let hf = fixture("volcano_33x33");
    let mut whole = EdgeDecimation::new(hf.clone(), DecimationParams::default()).unwrap();
    whole.run_to_end();
    let mut sliced = EdgeDecimation::new(hf, DecimationParams::default()).unwrap();
    while !sliced.step(3).done {}
    assert_eq!(whole.front(), sliced.front());
    assert_eq!(whole.recorded(), sliced.recorded());
}

#[test]
fn bad_decimation_params_are_refused() {
    let hf = single_bump(3, 3, 1, 1);
    // Each list's first value out of order or out of (0, 1) is the one named.
    for (reductions, refused) in [
        (vec![0.0], 0.0),
        (vec![0.2, 0.1], 0.1),
        (vec![1.0], 1.0),
        (vec![f64::NAN], f64::NAN),
    ] {
        let params = DecimationParams {
            reductions,
            ..DecimationParams::default()
        };
        match EdgeDecimation::new(hf.clone(), params) {
            Err(ParamsError::OutOfRange {
                name: "reductions",
                value,
                ..
            }) => assert!(value == refused || (value.is_nan() && refused.is_nan())),
            other => panic!("{:?}", other.err()),
        }
    }
}

#[test]
fn thin_and_tiny_grids_work() {
    // A 2-wide grid has no interior point: every insertion splits a border edge and every
    // removal re-triangulates a border fan. A 2×2 grid has nothing to insert or remove.
    let z: Vec<f64> = (0..2 * 6).map(|i| ((i * 7) % 5) as f64).collect();
    let hf = Arc::new(Heightfield::new(2, 6, z).unwrap());
    let mut run = greedy(&hf, InsertionRule::MaxError, GreedyStop::AllPoints);
    let mut ev = Evaluator::new(hf.clone());
    while !run.step(1).done {
        let evaluation = ev.evaluate(&run.kept()).unwrap();
        assert_eq!(
            canonical(&run.triangles()),
            canonical(&evaluation.triangles)
        );
    }
    assert_eq!(run.recorded().last().unwrap().t, hf.full_triangles());
    let mut dec = EdgeDecimation::new(hf.clone(), DecimationParams::default()).unwrap();
    dec.run_to_end();
    assert_eq!(dec.recorded().len(), 10);
    assert_rescores(
        &hf,
        &dec.recorded()
            .iter()
            .map(|(_, s)| s.clone())
            .collect::<Vec<_>>(),
    );

    let hf = Arc::new(Heightfield::new(2, 2, vec![0.0, 1.0, 2.0, 4.0]).unwrap());
    let mut run = greedy(&hf, InsertionRule::SumReduction, GreedyStop::AllPoints);
    assert_eq!(run.run_to_end().evaluations, 0);
    assert_eq!(run.front().len(), 1);
    let mut dec = EdgeDecimation::new(hf, DecimationParams::default()).unwrap();
    let p = dec.run_to_end();
    assert!(p.done && dec.recorded().is_empty() && dec.front().is_empty());
}

#[test]
fn params_round_trip_through_json() {
    // The CLI stores the parameters in front.json: they must read back identically, and an
    // empty object must mean the defaults.
    let greedy_params = GreedyParams {
        rule: InsertionRule::SumReduction,
        stop: GreedyStop::MaxErrorFraction(0.01),
        ..GreedyParams::default()
    };
    let text = serde_json::to_string(&greedy_params).unwrap();
    assert!(text.contains("\"sum-reduction\""), "{text}");
    assert_eq!(
        serde_json::from_str::<GreedyParams>(&text).unwrap(),
        greedy_params
    );
    assert_eq!(
        serde_json::from_str::<GreedyParams>("{}").unwrap(),
        GreedyParams::default()
    );
    let decimation = DecimationParams::default();
    let text = serde_json::to_string(&decimation).unwrap();
    assert_eq!(
        serde_json::from_str::<DecimationParams>(&text).unwrap(),
        decimation
    );
    assert_eq!(decimation.reductions.len(), 10);
}
