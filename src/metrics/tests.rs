//! The metrics module against hand-computed values, textbook tables, brute force and the
//! published examples of other implementations.

use crate::evaluator::Evaluator;
use crate::evaluator::test_grids::shared_fixture;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use crate::metrics::{
    self, DEFAULT_REFERENCE_POINT, MetricsError, Normalization, Point, RankSumMethod,
    additive_epsilon, best_error_pick, coverage, dominance_probability, exact_u_cdf,
    fewest_triangles_pick, hypervolume, hypervolume_ratio, merge, multiplicative_epsilon,
    non_dominated, rank_sum_test, rank_sum_test_with, strict_coverage, trade_off_pick,
    trade_off_pick_with,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;

fn assert_close(found: f64, expected: f64, tol: f64, what: &str) {
    assert!(
        (found - expected).abs() <= tol,
        "{what}: found {found}, expected {expected}"
    );
}

/// A small front (hypervolume 38 with reference point (10, 10)), in no particular order.
const EXAMPLE_FRONT: [Point; 4] = [[5.0, 5.0], [4.0, 6.0], [2.0, 7.0], [7.0, 4.0]];
const R10: Point = [10.0, 10.0];

// ---------------------------------------------------------------- non-dominated filtering

#[test]
fn non_dominated_keeps_each_objective_vector_once_sorted_by_t() {
    // (6, 6) is dominated by (5, 5); (5, 5) appears twice; (2, 9) is dominated by (2, 7) (same
    // E, more T); (8, 4) by (7, 4) (same T, more E).
    let points = [
        [6.0, 6.0],
        [5.0, 5.0],
        [2.0, 9.0],
        [4.0, 6.0],
        [5.0, 5.0],
        [8.0, 4.0],
        [2.0, 7.0],
        [7.0, 4.0],
    ];
    assert_eq!(
        non_dominated(&points).unwrap(),
        vec![[7.0, 4.0], [5.0, 5.0], [4.0, 6.0], [2.0, 7.0]]
    );
    assert_eq!(non_dominated(&[]).unwrap(), Vec::<Point>::new());
}

#[test]
fn merge_removes_points_duplicated_or_dominated_across_sets() {
    // Run 1 and run 2 share (4, 2); run 2's (3, 5) is dominated by run 1's (2, 4).
    let run1 = [[4.0, 2.0], [2.0, 4.0]];
    let run2 = [[4.0, 2.0], [3.0, 5.0], [1.0, 9.0]];
    let empty: [Point; 0] = [];
    assert_eq!(
        merge([&run1[..], &run2[..], &empty[..]]).unwrap(),
        vec![[4.0, 2.0], [2.0, 4.0], [1.0, 9.0]]
    );
    assert_eq!(merge([&empty[..]]).unwrap(), Vec::<Point>::new());
    assert!(matches!(
        merge([&run1[..], &[[f64::INFINITY, 1.0]][..]]),
        Err(MetricsError::NonFinite { .. })
    ));
}

#[test]
fn non_dominated_agrees_with_front_merged_on_random_solutions() {
    // Front::merged (incremental offers) and non_dominated (sort and sweep) are independent
    // implementations of the same set; small integer objectives make ties and duplicates common.
    let mut rng = Pcg64Mcg::seed_from_u64(7);
    for _ in 0..50 {
        let solutions: Vec<Solution> = (0..40)
            .map(|_| {
                Solution::recorded(
                    rng.random_range(0..20) as f64,
                    0.0,
                    rng.random_range(2..20),
                    vec![],
                )
            })
            .collect();
        let by_front = metrics::objectives(Front::merged(&solutions).solutions());
        let by_sweep = non_dominated(&metrics::objectives(&solutions)).unwrap();
        assert_eq!(by_sweep, by_front);
    }
}

// ---------------------------------------------------------------- hypervolume

#[test]
fn hypervolume_of_the_example_front_is_38() {
    // Sorted by E: (2,7), (4,6), (5,5), (7,4). Slabs between consecutive E values, each as tall
    // as r_T minus that point's T:
    //   (4−2)·(10−7) = 6, (5−4)·(10−6) = 4, (7−5)·(10−5) = 10, (10−7)·(10−4) = 18; sum 38.
    assert_eq!(hypervolume(&EXAMPLE_FRONT, R10).unwrap(), 38.0);
    let mut reversed = EXAMPLE_FRONT;
    reversed.reverse();
    assert_eq!(hypervolume(&reversed, R10).unwrap(), 38.0);
}

#[test]
fn hypervolume_of_empty_and_single_point_sets() {
    assert_eq!(hypervolume(&[], R10).unwrap(), 0.0);
    // (4, 6) alone: a (10−4) × (10−6) = 6 × 4 box.
    assert_eq!(hypervolume(&[[4.0, 6.0]], R10).unwrap(), 24.0);
}

#[test]
fn hypervolume_ignores_dominated_duplicate_and_outside_points() {
    let mut points = EXAMPLE_FRONT.to_vec();
    // (6, 6) and (9, 9) are dominated by (5, 5): their boxes are inside its box.
    points.extend([[6.0, 6.0], [9.0, 9.0]]);
    // Duplicates add no area.
    points.extend([[5.0, 5.0], [2.0, 7.0]]);
    // Not strictly better than the reference in both objectives: nothing to add, even though
    // (0, 10) and (10, 0) would dominate much of the box if they counted.
    points.extend([[0.0, 10.0], [10.0, 0.0], [11.0, 1.0], [1.0, 12.0]]);
    assert_eq!(hypervolume(&points, R10).unwrap(), 38.0);
}

#[test]
fn hypervolume_matches_counting_unit_cells() {
    // Integer points, integer reference: the dominated region is a union of unit cells, and the
    // cell [x, x+1] × [y, y+1] is dominated iff some point p has p ≤ (x, y).
    let mut rng = Pcg64Mcg::seed_from_u64(3);
    for _ in 0..30 {
        let n = rng.random_range(0..12);
        let points: Vec<Point> = (0..n)
            .map(|_| {
                [
                    rng.random_range(0..25) as f64,
                    rng.random_range(0..25) as f64,
                ]
            })
            .collect();
        let reference = [20.0, 22.0];
        let mut cells = 0;
        for x in 0..20 {
            for y in 0..22 {
                if points.iter().any(|p| p[0] <= x as f64 && p[1] <= y as f64) {
                    cells += 1;
                }
            }
        }
        assert_eq!(hypervolume(&points, reference).unwrap(), cells as f64);
    }
}

#[test]
fn hypervolume_rejects_nan() {
    assert_eq!(
        hypervolume(&[[1.0, 1.0], [f64::NAN, 2.0]], R10),
        Err(MetricsError::NonFinite {
            set: "points",
            index: 1
        })
    );
    assert!(matches!(
        hypervolume(&[[1.0, 1.0]], [f64::NAN, 1.0]),
        Err(MetricsError::NonFinite {
            set: "reference point",
            ..
        })
    ));
}

#[test]
fn hypervolume_ratio_against_the_merge_of_two_methods() {
    // Method A found (5,5), (2,7); method B found (4,6), (7,4). Their merge is EXAMPLE_FRONT
    // (HV 38).
    // HV(A): by T, (5,5) owns T 5..7 with width 10−5 → 10; (2,7) owns T 7..10 with width 8 → 24;
    // total 34.
    // HV(B): (7,4) owns T 4..6, width 3 → 6; (4,6) owns T 6..10, width 6 → 24; total 30.
    let a = [[5.0, 5.0], [2.0, 7.0]];
    let b = [[4.0, 6.0], [7.0, 4.0]];
    let reference_front = merge([&a[..], &b[..]]).unwrap();
    assert_eq!(hypervolume(&reference_front, R10).unwrap(), 38.0);
    assert_close(
        hypervolume_ratio(&a, &reference_front, R10).unwrap(),
        34.0 / 38.0,
        1e-15,
        "HVR(A)",
    );
    assert_close(
        hypervolume_ratio(&b, &reference_front, R10).unwrap(),
        30.0 / 38.0,
        1e-15,
        "HVR(B)",
    );
    assert_eq!(
        hypervolume_ratio(&reference_front, &reference_front, R10).unwrap(),
        1.0
    );
    // A reference front with nothing inside the reference box: the ratio is undefined.
    assert_eq!(
        hypervolume_ratio(&a, &[[10.0, 1.0]], R10),
        Err(MetricsError::ZeroReferenceHypervolume)
    );
    assert_eq!(
        hypervolume_ratio(&a, &[], R10),
        Err(MetricsError::ZeroReferenceHypervolume)
    );
}

// ---------------------------------------------------------------- epsilon

#[test]
fn additive_epsilon_hand_computed() {
    let a = [[1.0, 3.0], [3.0, 1.0]];
    let b = [[2.0, 2.0]];
    // For b = (2,2): a = (1,3) needs max(1−2, 3−2) = 1, a = (3,1) needs max(3−2, 1−2) = 1.
    assert_eq!(additive_epsilon(&a, &b).unwrap(), 1.0);
    // For a = (1,3): (2,2) needs max(2−1, 2−3) = 1; for a = (3,1): max(2−3, 2−1) = 1; max is 1.
    assert_eq!(additive_epsilon(&b, &a).unwrap(), 1.0);
    // A set against itself: each point covers itself with ε = 0.
    assert_eq!(additive_epsilon(&a, &a).unwrap(), 0.0);
    // (1,1) dominates (2,3) with room: max(1−2, 1−3) = −1 < 0.
    assert_eq!(
        additive_epsilon(&[[1.0, 1.0]], &[[2.0, 3.0]]).unwrap(),
        -1.0
    );
}

#[test]
fn additive_epsilon_is_the_worst_covered_point() {
    // B's points (2, 9) and (8, 2) against A = {(1, 8), (6, 5)}:
    //   (2, 9): from (1,8) max(−1, −1) = −1; from (6,5) max(4, −4) = 4 → min −1.
    //   (8, 2): from (1,8) max(−7, 6) = 6; from (6,5) max(−2, 3) = 3 → min 3.
    // The worst covered point sets ε: max(−1, 3) = 3.
    let a = [[1.0, 8.0], [6.0, 5.0]];
    let b = [[2.0, 9.0], [8.0, 2.0]];
    assert_eq!(additive_epsilon(&a, &b).unwrap(), 3.0);
}

#[test]
fn multiplicative_epsilon_hand_computed() {
    let a = [[2.0, 4.0]];
    let b = [[1.0, 8.0], [4.0, 2.0]];
    // (1, 8): max(2/1, 4/8) = 2; (4, 2): max(2/4, 4/2) = 2; max 2.
    assert_eq!(multiplicative_epsilon(&a, &b).unwrap(), 2.0);
    // Reverse: for a = (2, 4) the best of B is (1,8): max(1/2, 8/4) = 2 or (4,2): max(4/2, 2/4)
    // = 2 → 2.
    assert_eq!(multiplicative_epsilon(&b, &a).unwrap(), 2.0);
    assert_eq!(multiplicative_epsilon(&b, &b).unwrap(), 1.0);
    // (1, 1) dominates (2, 4): max(1/2, 1/4) = 0.5 < 1.
    assert_eq!(
        multiplicative_epsilon(&[[1.0, 1.0]], &[[2.0, 4.0]]).unwrap(),
        0.5
    );
}

#[test]
fn multiplicative_epsilon_is_scale_free_and_additive_is_shift_free() {
    let a = [[0.3, 0.1], [0.1, 0.5]];
    let b = [[0.2, 0.2], [0.05, 0.9]];
    let scaled = |s: &[Point]| {
        s.iter()
            .map(|p| [7.0 * p[0], 0.5 * p[1]])
            .collect::<Vec<_>>()
    };
    let shifted = |s: &[Point]| {
        s.iter()
            .map(|p| [p[0] + 3.0, p[1] - 1.0])
            .collect::<Vec<_>>()
    };
    assert_close(
        multiplicative_epsilon(&scaled(&a), &scaled(&b)).unwrap(),
        multiplicative_epsilon(&a, &b).unwrap(),
        1e-12,
        "scaled",
    );
    assert_close(
        additive_epsilon(&shifted(&a), &shifted(&b)).unwrap(),
        additive_epsilon(&a, &b).unwrap(),
        1e-12,
        "shifted",
    );
}

#[test]
fn multiplicative_epsilon_contract_on_zero_and_negative_values() {
    // B holds an exact mesh (E = 0). A point with E > 0 can never satisfy a_E ≤ ε·0: +∞.
    assert_eq!(
        multiplicative_epsilon(&[[1.0, 2.0]], &[[0.0, 5.0]]).unwrap(),
        f64::INFINITY
    );
    // A point with E = 0 too: the E objective sets no bound, T needs 4/5.
    assert_eq!(
        multiplicative_epsilon(&[[0.0, 4.0]], &[[0.0, 5.0]]).unwrap(),
        0.8
    );
    // E = 0 only in A: a ratio of 0 for E, T decides: max(0/2, 6/3) = 2.
    assert_eq!(
        multiplicative_epsilon(&[[0.0, 6.0]], &[[2.0, 3.0]]).unwrap(),
        2.0
    );
    assert_eq!(
        multiplicative_epsilon(&[[1.0, 2.0]], &[[-1.0, 5.0]]),
        Err(MetricsError::Negative { set: "B", index: 0 })
    );
    assert_eq!(
        multiplicative_epsilon(&[[1.0, 2.0], [1.0, -2.0]], &[[1.0, 5.0]]),
        Err(MetricsError::Negative { set: "A", index: 1 })
    );
}

#[test]
fn epsilon_rejects_empty_sets_and_nan() {
    assert_eq!(
        additive_epsilon(&[], &[[1.0, 1.0]]),
        Err(MetricsError::Empty { set: "A" })
    );
    assert_eq!(
        multiplicative_epsilon(&[[1.0, 1.0]], &[]),
        Err(MetricsError::Empty { set: "B" })
    );
    assert_eq!(
        additive_epsilon(&[[1.0, 1.0]], &[[1.0, f64::NAN]]),
        Err(MetricsError::NonFinite { set: "B", index: 0 })
    );
}

// ---------------------------------------------------------------- coverage

#[test]
fn coverage_of_a_set_by_itself() {
    // Zitzler's C uses weak dominance: every point covers itself, so C(A, A) = 1.
    let a = [[1.0, 5.0], [2.0, 3.0], [4.0, 1.0]];
    assert_eq!(coverage(&a, &a).unwrap(), 1.0);
    // The strict variant (where C(A, A) = 0): no point of a mutually non-dominated set
    // strictly dominates another.
    assert_eq!(strict_coverage(&a, &a).unwrap(), 0.0);
    // With a dominated member, strict C(A, A) is no longer 0: (3, 4) is dominated by (2, 3),
    // so 1 of the 4 points is covered.
    let with_dominated = [[1.0, 5.0], [2.0, 3.0], [4.0, 1.0], [3.0, 4.0]];
    assert_eq!(
        strict_coverage(&with_dominated, &with_dominated).unwrap(),
        0.25
    );
}

#[test]
fn coverage_when_a_dominates_b() {
    // Every point of B is strictly dominated by a point of A: (2,6) by (1,5), (3,4) by (2,3),
    // (5,2) by (4,1).
    let a = [[1.0, 5.0], [2.0, 3.0], [4.0, 1.0]];
    let b = [[2.0, 6.0], [3.0, 4.0], [5.0, 2.0]];
    assert_eq!(coverage(&a, &b).unwrap(), 1.0);
    assert_eq!(strict_coverage(&a, &b).unwrap(), 1.0);
    // No point of B is no worse than any point of A.
    assert_eq!(coverage(&b, &a).unwrap(), 0.0);
    assert_eq!(strict_coverage(&b, &a).unwrap(), 0.0);
}

#[test]
fn coverage_partial_and_shared_points() {
    // Both methods found the corner-only mesh (10, 2). B's (3, 7) is dominated by A's (3, 6);
    // B's (1, 12) is covered by nothing in A.
    let a = [[10.0, 2.0], [3.0, 6.0]];
    let b = [[10.0, 2.0], [3.0, 7.0], [1.0, 12.0], [6.0, 4.0]];
    // Weak: (10,2) equal, (3,7) dominated; (6,4) is not (A has T ≤ 4 only at E = 10): 2 of 4.
    assert_eq!(coverage(&a, &b).unwrap(), 0.5);
    // Strict: the shared point no longer counts: 1 of 4.
    assert_eq!(strict_coverage(&a, &b).unwrap(), 0.25);
    // The other way: (10, 2) is shared (weak only); (3, 6) is not covered by any point of B
    // ((3,7) has more T, (6,4) more E): 1 of 2 weak, 0 of 2 strict.
    assert_eq!(coverage(&b, &a).unwrap(), 0.5);
    assert_eq!(strict_coverage(&b, &a).unwrap(), 0.0);
}

#[test]
fn coverage_edge_cases() {
    assert_eq!(coverage(&[], &[[1.0, 1.0]]).unwrap(), 0.0);
    assert_eq!(
        coverage(&[[1.0, 1.0]], &[]),
        Err(MetricsError::Empty { set: "B" })
    );
    assert_eq!(
        strict_coverage(&[[f64::NAN, 1.0]], &[[1.0, 1.0]]),
        Err(MetricsError::NonFinite { set: "A", index: 0 })
    );
}

// ---------------------------------------------------------------- dominance probability

#[test]
fn dominance_probability_counts_dominating_pairs() {
    // A × B has 6 pairs. (1,4) dominates (2,5) and (1,6); (3,1) dominates (4,2); (1,4) vs (4,2)
    // and (3,1) vs (2,5), (1,6) are incomparable: 3 of 6.
    let a = [[1.0, 4.0], [3.0, 1.0]];
    let b = [[2.0, 5.0], [4.0, 2.0], [1.0, 6.0]];
    assert_eq!(dominance_probability(&a, &b).unwrap(), 0.5);
    // No point of B dominates a point of A.
    assert_eq!(dominance_probability(&b, &a).unwrap(), 0.0);
    // Equal points do not dominate each other.
    assert_eq!(dominance_probability(&a, &a).unwrap(), 0.0);
    assert_eq!(
        dominance_probability(&[], &b),
        Err(MetricsError::Empty { set: "A" })
    );
}

// ---------------------------------------------------------------- normalisation

/// A 3×3 grid, flat except the centre at height 1.
fn bump() -> Heightfield {
    Heightfield::new(3, 3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]).unwrap()
}

#[test]
fn normalization_from_the_corner_only_mesh_and_the_full_grid() {
    // The corner-only mesh of the bump is flat at 0: it misses only the centre, by 1, so E = 1.
    // The full 3×3 grid has 2·2·2 = 8 triangles.
    let mut evaluator = Evaluator::new(Arc::new(bump()));
    let n = Normalization::from_evaluator(&mut evaluator).unwrap();
    assert_eq!((n.e_scale(), n.t_scale()), (1.0, 8.0));
    assert_eq!(n.apply([0.5, 4.0]), [0.5, 0.5]);
    assert_eq!(n.invert([0.5, 0.5]), [0.5, 4.0]);
}

#[test]
fn normalization_of_a_plane_is_an_error_not_a_division_by_zero() {
    // z = x + 2y: the corner-only mesh is exact, E = 0.
    let z: Vec<f64> = (0..9)
        .map(|i| (i % 3) as f64 + 2.0 * (i / 3) as f64)
        .collect();
    let mut evaluator = Evaluator::new(Arc::new(Heightfield::new(3, 3, z).unwrap()));
    assert_eq!(
        Normalization::from_evaluator(&mut evaluator),
        Err(MetricsError::BadScale {
            objective: "E",
            value: 0.0
        })
    );
}

#[test]
fn normalization_rejects_bad_scales() {
    for (e, t) in [
        (0.0, 1.0),
        (1.0, -2.0),
        (f64::NAN, 1.0),
        (1.0, f64::INFINITY),
    ] {
        assert!(matches!(
            Normalization::new(e, t),
            Err(MetricsError::BadScale { .. })
        ));
    }
    assert!(Normalization::new(2.0, 3.0).is_ok());
}

#[test]
fn normalised_meshes_of_a_real_dataset_lie_where_the_reference_point_assumes() {
    // DEFAULT_REFERENCE_POINT's justification: normalised T ≤ 1 for every mesh, and the
    // corner-only mesh sits at E = 1.
    let hf = shared_fixture("jacksboro_33x33");
    let mut evaluator = Evaluator::new(hf.clone());
    let n = Normalization::from_evaluator(&mut evaluator).unwrap();
    assert_eq!(n.t_scale(), 2048.0); // 2·32·32
    let corner = evaluator.score(&hf.corners()).unwrap();
    assert_eq!(
        n.apply([corner.e_sum, corner.t as f64]),
        [1.0, 2.0 / 2048.0]
    );
    let mut rng = Pcg64Mcg::seed_from_u64(11);
    let mut points = vec![];
    for fraction in [0.05, 0.2, 0.5, 1.0] {
        let kept: Vec<u32> = (0..hf.len() as u32)
            .filter(|_| rng.random::<f64>() < fraction)
            .collect();
        let s = evaluator.score(&kept).unwrap();
        points.push(n.apply([s.e_sum, s.t as f64]));
    }
    assert!(points.iter().all(|p| p[1] <= 1.0), "{points:?}");
    // Keeping everything is exact and has every triangle.
    assert_eq!(points[3], [0.0, 1.0]);
    // The full mesh contributes the slab (1.1 − 0) × (1.1 − 1): the extremes count.
    let hv = hypervolume(&[[0.0, 1.0]], DEFAULT_REFERENCE_POINT).unwrap();
    assert_close(hv, 1.1 * 0.1, 1e-12, "full-mesh slab");
    // Scaling by (e_scale, t_scale) divides every hypervolume by their product.
    let raw: Vec<Point> = points.iter().map(|&p| n.invert(p)).collect();
    let raw_reference = n.invert(DEFAULT_REFERENCE_POINT);
    assert_close(
        hypervolume(&points, DEFAULT_REFERENCE_POINT).unwrap(),
        hypervolume(&raw, raw_reference).unwrap() / (n.e_scale() * n.t_scale()),
        1e-12,
        "normalised HV",
    );
}

// ---------------------------------------------------------------- Wilcoxon rank-sum

/// The number of k-subsets of 1..=n with each rank sum, by enumeration (no recurrence).
fn brute_force_u_counts(n1: usize, n2: usize) -> Vec<u64> {
    let n = n1 + n2;
    let mut counts = vec![0u64; n1 * n2 + 1];
    for mask in 0u32..(1 << n) {
        if mask.count_ones() as usize != n1 {
            continue;
        }
        let rank_sum: usize = (0..n).filter(|i| mask >> i & 1 == 1).map(|i| i + 1).sum();
        counts[rank_sum - n1 * (n1 + 1) / 2] += 1;
    }
    counts
}

#[test]
fn exact_u_distribution_matches_enumeration() {
    for (n1, n2) in [(1, 1), (1, 5), (3, 4), (4, 6), (6, 7), (7, 3)] {
        let counts = brute_force_u_counts(n1, n2);
        let total: u64 = counts.iter().sum();
        let mut below = 0;
        for (u, c) in counts.iter().enumerate() {
            below += c;
            assert_close(
                exact_u_cdf(n1, n2, u).unwrap(),
                below as f64 / total as f64,
                1e-14,
                &format!("P(U ≤ {u}) for sizes {n1}, {n2}"),
            );
        }
    }
    // Sizes 3 and 4: U = 0 only when the three lowest ranks all belong to sample 1: 1 of
    // C(7, 3) = 35.
    assert_close(exact_u_cdf(3, 4, 0).unwrap(), 1.0 / 35.0, 1e-15, "1/35");
    assert_eq!(exact_u_cdf(3, 4, 12).unwrap(), 1.0);
}

#[test]
fn exact_p_value_for_n5_n5_u2_is_0_0317() {
    // Mann–Whitney table (e.g. Siegel & Castellan, Nonparametric Statistics, table J):
    // n1 = n2 = 5, U = 2: one-sided P = 4/252 (U = 0, 1, 2 reached by 1, 1, 2 rank sets), so
    // two-sided p = 8/252 = 0.0317.
    // x = 1, 2, 3, 4, 7 and y = 5, 6, 8, 9, 10: only 7 > 5 and 7 > 6, so U1 = 2.
    let t = rank_sum_test(&[1.0, 2.0, 3.0, 4.0, 7.0], &[5.0, 6.0, 8.0, 9.0, 10.0]).unwrap();
    assert_eq!((t.u1, t.u2), (2.0, 23.0));
    assert_eq!(t.method, RankSumMethod::Exact);
    assert_close(t.p_value, 8.0 / 252.0, 1e-15, "p");
    assert_close(t.p_value, 0.0317, 5e-5, "p (table)");
}

#[test]
fn exact_p_values_reproduce_the_critical_value_table() {
    // Critical values of U for a two-sided test at α = 0.05 with n1 = n2 = n (the standard
    // Mann–Whitney table): the largest U with two-sided p ≤ 0.05.
    for (n, critical) in [
        (5, 2),
        (6, 5),
        (7, 8),
        (8, 13),
        (9, 17),
        (10, 23),
        (20, 127),
    ] {
        let p = |u: usize| 2.0 * exact_u_cdf(n, n, u).unwrap();
        assert!(
            p(critical) <= 0.05,
            "n = {n}: p(U={critical}) = {}",
            p(critical)
        );
        assert!(
            p(critical + 1) > 0.05,
            "n = {n}: p(U={}) too small",
            critical + 1
        );
    }
}

#[test]
fn rank_sum_reproduces_the_scipy_documentation_example() {
    // SciPy's `mannwhitneyu` docs: males 19, 22, 16, 29, 24 against females 20, 11, 17, 12.
    // U1 = 3 + 4 + 2 + 4 + 4 = 17 (pairs male > female). Exact: U2 = 3 and P(U ≤ 3) = (1 + 1
    // + 2 + 3)/C(9, 4) = 7/126, so p = 14/126 = 0.1111 (SciPy: 0.1111111111111111).
    // Asymptotic: μ = 10, σ² = 5·4·10/12, z = (17 − 10 − 0.5)/σ = 1.5922, p = 0.11134688653314041.
    let males = [19.0, 22.0, 16.0, 29.0, 24.0];
    let females = [20.0, 11.0, 17.0, 12.0];
    let exact = rank_sum_test(&males, &females).unwrap();
    assert_eq!(exact.u1, 17.0);
    assert_eq!(exact.method, RankSumMethod::Exact);
    assert_close(exact.p_value, 1.0 / 9.0, 1e-15, "exact p");
    let normal = rank_sum_test_with(&males, &females, RankSumMethod::Normal).unwrap();
    assert_close(normal.p_value, 0.11134688653314041, 1e-15, "asymptotic p");
    assert_close(
        normal.z.unwrap(),
        6.5 / (200.0f64 / 12.0).sqrt(),
        1e-12,
        "z",
    );
}

#[test]
fn rank_sum_completely_separated_samples() {
    // SciPy: mannwhitneyu([1..5], [6..10]) = (U 0, p 0.007936507936507936) = 2/252.
    let t = rank_sum_test(&[1.0, 2.0, 3.0, 4.0, 5.0], &[6.0, 7.0, 8.0, 9.0, 10.0]).unwrap();
    assert_eq!(t.u1, 0.0);
    assert_close(t.p_value, 0.007936507936507936, 1e-15, "p");
    assert_eq!(t.prob_first_larger(), 0.0);
}

#[test]
fn rank_sum_verdict_gives_the_direction_of_a_significant_difference() {
    use std::cmp::Ordering;
    // p = 2/252 = 0.0079: significant at 0.05 and at 0.01, not at 0.005.
    let low = [1.0, 2.0, 3.0, 4.0, 5.0];
    let high = [6.0, 7.0, 8.0, 9.0, 10.0];
    let t = rank_sum_test(&low, &high).unwrap();
    assert_eq!(t.verdict(0.05), Ordering::Less);
    assert_eq!(t.verdict(0.01), Ordering::Less);
    assert_eq!(t.verdict(0.005), Ordering::Equal);
    assert_eq!(
        rank_sum_test(&high, &low).unwrap().verdict(0.05),
        Ordering::Greater
    );
    // p = 0.1111 (the SciPy example): not significant at 0.05.
    let t = rank_sum_test(&[19.0, 22.0, 16.0, 29.0, 24.0], &[20.0, 11.0, 17.0, 12.0]).unwrap();
    assert_eq!(t.verdict(0.05), Ordering::Equal);
    assert_eq!(t.verdict(f64::NAN), Ordering::Equal);
}

#[test]
fn rank_sum_normal_approximation_with_heavy_ties() {
    // x = 1,1,1,2,2 and y = 2,2,3,3,3. Tie groups: three 1s (ranks 1–3, midrank 2), four 2s
    // (ranks 4–7, midrank 5.5), three 3s (ranks 8–10, midrank 9).
    // R1 = 3·2 + 2·5.5 = 17, U1 = 17 − 15 = 2, μ = 12.5.
    // Σ(t³ − t) = 24 + 60 + 24 = 108; σ² = 25/12·(11 − 108/90) = 25/12·9.8 = 20.41667.
    // z = (2 − 12.5 + 0.5)/√20.41667 = −2.2131333; p = erfc(2.2131333/√2) = 0.0268885.
    let x = [1.0, 1.0, 1.0, 2.0, 2.0];
    let y = [2.0, 2.0, 3.0, 3.0, 3.0];
    let t = rank_sum_test(&x, &y).unwrap();
    assert_eq!(t.method, RankSumMethod::Normal);
    assert_eq!(t.u1, 2.0);
    assert_close(t.z.unwrap(), -2.2131333406899527, 1e-12, "z");
    assert_close(t.p_value, 0.026888454103745792, 1e-15, "p");
    assert_eq!(
        rank_sum_test_with(&x, &y, RankSumMethod::Exact),
        Err(MetricsError::ExactWithTies)
    );
}

#[test]
fn rank_sum_of_identical_samples_is_p_1() {
    // Identical samples tie pairwise: U1 = U2 = n1·n2/2, the continuity-corrected z is 0.
    let x = [0.8, 0.9, 0.95, 0.7];
    let t = rank_sum_test(&x, &x).unwrap();
    assert_eq!((t.u1, t.p_value), (8.0, 1.0));
    // All values equal: the variance is 0, and p = 1 by definition.
    let t = rank_sum_test(&[3.0; 4], &[3.0; 6]).unwrap();
    assert_eq!((t.u1, t.p_value), (12.0, 1.0));
    // Exact at the centre: x = 1, 4 and y = 2, 3 give U1 = 2 = n1·n2/2; 2·P(U ≤ 2) ≥ 1 → 1.
    let t = rank_sum_test(&[1.0, 4.0], &[2.0, 3.0]).unwrap();
    assert_eq!((t.method, t.p_value), (RankSumMethod::Exact, 1.0));
}

#[test]
fn rank_sum_is_symmetric_in_its_samples() {
    let x = [0.61, 0.72, 0.55, 0.80, 0.66, 0.59];
    let y = [0.70, 0.75, 0.81, 0.77, 0.69];
    for method in [RankSumMethod::Exact, RankSumMethod::Normal] {
        let xy = rank_sum_test_with(&x, &y, method).unwrap();
        let yx = rank_sum_test_with(&y, &x, method).unwrap();
        assert_eq!((xy.u1, xy.u2), (yx.u2, yx.u1));
        assert_close(xy.p_value, yx.p_value, 1e-15, "p");
    }
}

#[test]
fn rank_sum_auto_switches_to_normal_at_50_and_agrees_with_exact_there() {
    // 49 vs 49: exact. 50 vs 50: normal. Sample 2 is sample 1 shifted by 7.5 ranks' worth, so
    // the two methods must give close p-values (the normal approximation is good at this size).
    let x: Vec<f64> = (0..49).map(|i| i as f64).collect();
    let y: Vec<f64> = (0..49).map(|i| i as f64 + 7.5).collect();
    let exact = rank_sum_test(&x, &y).unwrap();
    assert_eq!(exact.method, RankSumMethod::Exact);
    let normal = rank_sum_test_with(&x, &y, RankSumMethod::Normal).unwrap();
    assert_close(exact.p_value, normal.p_value, 0.005, "exact vs normal");
    let x50: Vec<f64> = (0..50).map(|i| i as f64).collect();
    let y50: Vec<f64> = (0..50).map(|i| i as f64 + 7.5).collect();
    assert_eq!(
        rank_sum_test(&x50, &y50).unwrap().method,
        RankSumMethod::Normal
    );
}

#[test]
fn rank_sum_rejects_bad_samples() {
    assert_eq!(
        rank_sum_test(&[], &[1.0]),
        Err(MetricsError::Empty { set: "sample 1" })
    );
    assert_eq!(
        rank_sum_test(&[1.0], &[2.0, f64::NAN]),
        Err(MetricsError::NonFinite {
            set: "sample 2",
            index: 1
        })
    );
    let big: Vec<f64> = (0..101).map(|i| i as f64).collect();
    let other: Vec<f64> = (0..100).map(|i| i as f64 + 0.5).collect();
    assert_eq!(
        rank_sum_test_with(&big, &other, RankSumMethod::Exact),
        Err(MetricsError::ExactTooLarge { n1: 101, n2: 100 })
    );
    assert_eq!(
        exact_u_cdf(0, 3, 0),
        Err(MetricsError::Empty { set: "sample 1" })
    );
}

// ---------------------------------------------------------------- picks

#[test]
fn picks_on_a_three_point_front() {
    // T/E = 2/10, 4/4, 10/1 → α = (0.2 + 1 + 10)/3 = 3.7333. At the mean weight w̄ ≈ 0.5 the
    // scores are about ½(α·E + T): (10,2) → 19.7, (4,4) → 9.5, (1,10) → 6.9: the last wins.
    let front = [[10.0, 2.0], [4.0, 4.0], [1.0, 10.0]];
    let pick = trade_off_pick(&front, 42).unwrap();
    assert_eq!(pick.index, 2);
    assert_close(pick.alpha, 11.2 / 3.0, 1e-12, "alpha");
    assert_close(pick.mean_weight, 0.5, 0.05, "mean weight");
    // The mean of a linear score is the score at the mean weight.
    let w = pick.mean_weight;
    assert_close(
        pick.mean_score,
        pick.alpha * w * 1.0 + (1.0 - w) * 10.0,
        1e-9,
        "mean score",
    );
    assert_eq!(best_error_pick(&front).unwrap(), 2);
    assert_eq!(fewest_triangles_pick(&front).unwrap(), 0);
}

#[test]
fn trade_off_pick_can_be_an_interior_point() {
    // T/E = 2/8, 3/2, 8/1.5 → α = (0.25 + 1.5 + 5.3333)/3 = 2.3611. Half-scores ½(α·E + T): (8,2) → 10.44,
    // (2,3) → 3.86, (1.5,8) → 5.77: the middle wins.
    let front = [[8.0, 2.0], [2.0, 3.0], [1.5, 8.0]];
    let pick = trade_off_pick(&front, 1).unwrap();
    assert_eq!(pick.index, 1);
    assert_ne!(pick.index, best_error_pick(&front).unwrap());
    assert_ne!(pick.index, fewest_triangles_pick(&front).unwrap());
}

#[test]
fn trade_off_pick_is_deterministic_and_scale_free() {
    let front = [
        [0.9, 0.01],
        [0.4, 0.05],
        [0.2, 0.1],
        [0.05, 0.5],
        [0.01, 1.0],
    ];
    let a = trade_off_pick(&front, 5).unwrap();
    let b = trade_off_pick(&front, 5).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.mean_score.to_bits(), b.mean_score.to_bits());
    // The same front in raw units (E × 1234, T × 2048) picks the same solution.
    let raw: Vec<Point> = front
        .iter()
        .map(|p| [p[0] * 1234.0, p[1] * 2048.0])
        .collect();
    assert_eq!(trade_off_pick(&raw, 5).unwrap().index, a.index);
    // The caller's generator is used: a seeded Pcg64Mcg gives the same as the seed.
    let mut rng = Pcg64Mcg::seed_from_u64(5);
    assert_eq!(trade_off_pick_with(&front, &mut rng, 1000).unwrap(), a);
}

#[test]
fn trade_off_pick_with_an_exact_mesh() {
    // (0, 8) has E = 0: T/E is infinite, so α = mean(4/2, 2/6) = 7/6 over the others.
    // Half-scores: (0,8) → 4, (2,4) → ½(7/3 + 4) = 3.17, (6,2) → ½(7 + 2) = 4.5.
    let front = [[0.0, 8.0], [2.0, 4.0], [6.0, 2.0]];
    let pick = trade_off_pick(&front, 9).unwrap();
    assert_close(pick.alpha, 7.0 / 6.0, 1e-12, "alpha");
    assert_eq!(pick.index, 1);
    assert!(pick.mean_score.is_finite());
    assert_eq!(best_error_pick(&front).unwrap(), 0);
    // Only exact meshes: α = 0, the score is (1 − w)·T, fewest triangles wins.
    let pick = trade_off_pick(&[[0.0, 9.0], [0.0, 4.0]], 9).unwrap();
    assert_eq!((pick.index, pick.alpha), (1, 0.0));
}

#[test]
fn picks_break_ties_deterministically() {
    // Identical points: the first one.
    assert_eq!(
        trade_off_pick(&[[2.0, 4.0], [2.0, 4.0]], 0).unwrap().index,
        0
    );
    // Equal E: the lower T; equal T: the lower E.
    assert_eq!(best_error_pick(&[[1.0, 9.0], [1.0, 5.0]]).unwrap(), 1);
    assert_eq!(fewest_triangles_pick(&[[3.0, 2.0], [1.0, 2.0]]).unwrap(), 1);
}

#[test]
fn picks_reject_bad_fronts() {
    assert_eq!(
        trade_off_pick(&[], 0),
        Err(MetricsError::Empty { set: "front" })
    );
    assert_eq!(
        best_error_pick(&[[1.0, f64::NAN]]),
        Err(MetricsError::NonFinite {
            set: "front",
            index: 0
        })
    );
    assert_eq!(
        fewest_triangles_pick(&[[1.0, 2.0], [-1.0, 2.0]]),
        Err(MetricsError::Negative {
            set: "front",
            index: 1
        })
    );
    let mut rng = Pcg64Mcg::seed_from_u64(0);
    assert_eq!(
        trade_off_pick_with(&[[1.0, 2.0]], &mut rng, 0),
        Err(MetricsError::Empty { set: "weights" })
    );
}

#[test]
fn errors_have_readable_messages() {
    let e = multiplicative_epsilon(&[[1.0, 2.0]], &[[-1.0, 5.0]]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "B: point 0 has a negative objective; this indicator needs E ≥ 0 and T ≥ 0"
    );
    assert!(
        MetricsError::ExactTooLarge { n1: 200, n2: 200 }
            .to_string()
            .contains("10000")
    );
}
