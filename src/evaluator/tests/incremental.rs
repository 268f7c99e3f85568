//! Incremental evaluation ([`Evaluator::edit`]) against fresh evaluation ([`Evaluator::score`]):
//! the same triangles and the same score, bit for bit, over seeded random kept sets and random
//! edit sequences, plus tiny hand-made cases.

use crate::evaluator::canonical_set as triangle_set;
use crate::evaluator::test_grids::{
    bits, random_subset as random_kept, shared_fixture as fixture, synthetic,
};
use crate::evaluator::{Changes, EvaluateError, Evaluator, MeshState};
use crate::heightfield::Heightfield;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;

/// Checks `state` (after edits) against a fresh evaluation of its kept set.
fn assert_matches_fresh(ev: &mut Evaluator, state: &MeshState, n: usize, what: &str) {
    let kept: Vec<u32> = (0..n as u32).filter(|&i| state.is_kept(i)).collect();
    let fresh = ev.evaluate(&kept).unwrap();
    assert_eq!(
        bits(state.score().unwrap()),
        bits(fresh.score),
        "{what}: score {:?} vs fresh {:?}",
        state.score(),
        fresh.score
    );
    assert_eq!(
        triangle_set(&state.triangles()),
        triangle_set(&fresh.triangles),
        "{what}: triangles"
    );
}

/// The points of `flip` (distinct) as an edit of `state`: the kept ones to remove, the others
/// to insert, each in `flip`'s order.
fn as_edit(state: &MeshState, flip: impl IntoIterator<Item = u32>) -> (Vec<u32>, Vec<u32>) {
    flip.into_iter().partition(|&i| state.is_kept(i))
}

/// A random edit of `state`: each free point flips with probability `p` (removals of kept
/// points, insertions of the others), corners excluded, in random order.
fn random_edit(
    state: &MeshState,
    hf: &Heightfield,
    p: f64,
    rng: &mut Pcg64Mcg,
) -> (Vec<u32>, Vec<u32>) {
    let corners = hf.corners();
    let flip: Vec<u32> = (0..hf.len() as u32)
        .filter(|i| !corners.contains(i) && rng.random::<f64>() < p)
        .collect();
    let (mut remove, mut insert) = as_edit(state, flip);
    // Shuffle, so that the order of the edits is not always increasing.
    for list in [&mut remove, &mut insert] {
        for k in (1..list.len()).rev() {
            list.swap(k, rng.random_range(0..=k));
        }
    }
    (remove, insert)
}

/// Runs `rounds` random edits of random sizes from a random start on `hf`.
fn edit_sequences(hf: Arc<Heightfield>, seed: u64, rounds: usize) {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut ev = Evaluator::new(hf.clone());
    let n = hf.len();
    let mut state = MeshState::default();
    let density = [0.02, 0.1, 0.3, 0.7, 1.0][rng.random_range(0..5)];
    let kept = random_kept(n, density, &mut rng);
    ev.score_into(&kept, &mut state).unwrap();
    assert_matches_fresh(&mut ev, &state, n, "start");
    for round in 0..rounds {
        // Mostly small edits (a mutation), sometimes large ones (a crossover).
        let p = [0.5 / n as f64, 3.0 / n as f64, 0.02, 0.2, 0.6][rng.random_range(0..5)];
        let (remove, insert) = random_edit(&state, &hf, p, &mut rng);
        let score = ev.edit(&mut state, &remove, &insert).unwrap();
        assert_eq!(Some(score), state.score());
        let what = format!(
            "{}×{} seed {seed} round {round} (−{} +{})",
            hf.width(),
            hf.height(),
            remove.len(),
            insert.len()
        );
        assert_matches_fresh(&mut ev, &state, n, &what);
    }
}

#[test]
fn edits_match_fresh_evaluation_on_synthetic_grids() {
    // Thin grids (every point on the border), odd shapes, integer heights (exact ties) and real
    // heights.
    for (w, h) in [(2, 2), (2, 7), (7, 2), (3, 3), (5, 4), (9, 9), (17, 11)] {
        for seed in 0..6 {
            edit_sequences(synthetic(w, h, seed), seed, 25);
        }
    }
}

#[test]
fn edits_match_fresh_evaluation_on_real_data() {
    for (name, seed) in [
        ("jacksboro_33x33", 1),
        ("volcano_33x33", 2),
        ("camera_33x33", 3),
    ] {
        edit_sequences(fixture(name), seed, 30);
    }
}

#[test]
fn block_swaps_like_crossover_rows_match() {
    // An OAX row takes whole rectangles of genes from another parent: edits come in compact
    // blocks with many removals and insertions side by side, and chains of such edits (a row
    // edited from an earlier row) accumulate in one state.
    let hf = fixture("jacksboro_33x33");
    let (w, h) = (hf.width(), hf.height());
    let mut rng = Pcg64Mcg::seed_from_u64(17);
    let mut ev = Evaluator::new(hf.clone());
    let mut state = MeshState::default();
    ev.score_into(&random_kept(hf.len(), 0.2, &mut rng), &mut state)
        .unwrap();
    for round in 0..40 {
        let other = random_kept(hf.len(), rng.random::<f64>() * 0.6, &mut rng);
        let mut other_mark = vec![false; hf.len()];
        for &i in &other {
            other_mark[i as usize] = true;
        }
        let (x0, y0) = (rng.random_range(0..w), rng.random_range(0..h));
        let (x1, y1) = (rng.random_range(x0 + 1..=w), rng.random_range(y0 + 1..=h));
        let block = (y0..y1).flat_map(|y| (x0..x1).map(move |x| (y * w + x) as u32));
        let (remove, insert) = as_edit(
            &state,
            block.filter(|&i| {
                !hf.corners().contains(&i) && state.is_kept(i) != other_mark[i as usize]
            }),
        );
        ev.edit(&mut state, &remove, &insert).unwrap();
        let what = format!("round {round} block {x0}..{x1}×{y0}..{y1}");
        assert_matches_fresh(&mut ev, &state, hf.len(), &what);
    }
}

#[test]
fn edits_near_borders_and_corners_match() {
    // Only border points and their inner neighbours change: border removals leave an open fan
    // whose hole is closed by a border segment, border insertions split a border edge.
    let hf = synthetic(12, 9, 5);
    let (w, h) = (12u32, 9u32);
    let near_border: Vec<u32> = (0..w * h)
        .filter(|&i| {
            let (x, y) = (i % w, i / w);
            x <= 1 || y <= 1 || x >= w - 2 || y >= h - 2
        })
        .filter(|i| !hf.corners().contains(i))
        .collect();
    let mut rng = Pcg64Mcg::seed_from_u64(11);
    let mut ev = Evaluator::new(hf.clone());
    let mut state = MeshState::default();
    ev.score_into(&random_kept(hf.len(), 0.3, &mut rng), &mut state)
        .unwrap();
    for round in 0..200 {
        let k = rng.random_range(1..6);
        let mut flip = Vec::new();
        for _ in 0..k {
            let i = near_border[rng.random_range(0..near_border.len())];
            if !flip.contains(&i) {
                flip.push(i);
            }
        }
        let (remove, insert) = as_edit(&state, flip);
        ev.edit(&mut state, &remove, &insert).unwrap();
        assert_matches_fresh(&mut ev, &state, hf.len(), &format!("round {round}"));
    }
}

#[test]
fn co_circular_grid_points_take_the_tie_rule_diagonal() {
    // A 4×4 grid with all points kept (heights i², so that errors are not zero): every grid
    // square is a co-circular quadruple. Removing and re-inserting interior points one at a time must keep choosing
    // the same diagonals as a fresh build (the tie rule), or the triangle sets would differ.
    let hf = Arc::new(Heightfield::new(4, 4, (0..16).map(|i| (i * i) as f64).collect()).unwrap());
    let mut ev = Evaluator::new(hf.clone());
    let mut state = MeshState::default();
    ev.score_into(&(0..16).collect::<Vec<_>>(), &mut state)
        .unwrap();
    for (remove, insert) in [
        (vec![5], vec![]),
        (vec![6, 9], vec![]),
        (vec![], vec![5, 6]),
        (vec![10, 1, 13], vec![9]),
        (vec![4, 7, 8, 11], vec![10, 13]),
        (vec![2, 14], vec![1, 4, 7, 8, 11]),
    ] {
        ev.edit(&mut state, &remove, &insert).unwrap();
        assert_matches_fresh(&mut ev, &state, 16, &format!("−{remove:?} +{insert:?}"));
    }
}

#[test]
fn one_point_in_the_middle_of_a_3x3_grid() {
    // Bump of 4 in the middle of a flat 3×3 grid: inserting it takes E from 4 to 0 and T from
    // 2 to 4, removing it again restores the corner mesh exactly.
    let mut z = vec![0.0; 9];
    z[4] = 4.0;
    let hf = Arc::new(Heightfield::new(3, 3, z).unwrap());
    let mut ev = Evaluator::new(hf);
    let mut state = MeshState::default();
    let corners = ev.score_into(&[], &mut state).unwrap();
    assert_eq!((corners.e_sum, corners.t), (4.0, 2));
    let bump = ev.edit(&mut state, &[], &[4]).unwrap();
    assert_eq!((bump.e_sum, bump.e_max, bump.t), (0.0, 0.0, 4));
    let back = ev.edit(&mut state, &[4], &[]).unwrap();
    assert_eq!(bits(back), bits(corners));
}

#[test]
fn a_border_point_splits_a_border_edge() {
    // 3×2 grid, corners only: the middle of the bottom edge (index 1, height 6) lies on the
    // border edge 0–2, where z̃ = 0; inserting it splits that edge (no neighbour across it),
    // giving 3 triangles and no error.
    let hf = Arc::new(Heightfield::new(3, 2, vec![0.0, 6.0, 0.0, 0.0, 0.0, 0.0]).unwrap());
    let mut ev = Evaluator::new(hf);
    let mut state = MeshState::default();
    assert_eq!(ev.score_into(&[], &mut state).unwrap().e_sum, 6.0);
    let s = ev.edit(&mut state, &[], &[1]).unwrap();
    assert_eq!((s.e_sum, s.t), (0.0, 3));
    assert_matches_fresh(&mut ev, &state, 6, "border split");
}

#[test]
fn invalid_edits_are_refused_and_leave_the_state_unchanged() {
    // Removing a point that is not kept, removing a corner, inserting a kept point or an index
    // past the grid: each is a typed error, and the state still scores as before.
    let hf = synthetic(5, 5, 3);
    let mut ev = Evaluator::new(hf.clone());
    let mut state = MeshState::default();
    let before = ev.score_into(&[7, 12], &mut state).unwrap();
    let corner = hf.corners()[1];
    assert!(matches!(
        ev.edit(&mut state, &[7, 8], &[]),
        Err(EvaluateError::InvalidEdit { index: 8, .. })
    ));
    assert!(matches!(
        ev.edit(&mut state, &[corner], &[]),
        Err(EvaluateError::InvalidEdit { .. })
    ));
    assert!(matches!(
        ev.edit(&mut state, &[], &[13, 12]),
        Err(EvaluateError::InvalidEdit { index: 12, .. })
    ));
    assert_eq!(
        ev.edit(&mut state, &[], &[25]),
        Err(EvaluateError::IndexOutOfRange { index: 25, len: 25 })
    );
    assert!((0..25).all(|i| state.is_kept(i) == ([0, 4, 7, 12, 20, 24].contains(&i))));
    let unchanged = ev.edit(&mut state, &[], &[]).unwrap();
    assert_eq!(bits(unchanged), bits(before));
    // A state never scored, or scored on another height field, cannot be edited.
    assert_eq!(
        ev.edit(&mut MeshState::default(), &[], &[3]),
        Err(EvaluateError::ForeignState)
    );
    let mut other = Evaluator::new(synthetic(5, 5, 3));
    assert_eq!(
        other.edit(&mut state, &[], &[3]),
        Err(EvaluateError::ForeignState)
    );
}

#[test]
fn a_one_pass_score_equals_an_editable_build() {
    // `score` sums each triangle's errors without storing them; `score_into` stores every
    // point's error for later edits and sums the rows. Fixed-point totals make the two agree to
    // the bit whatever the order, on every density and on ties-heavy integer heights.
    let mut rng = Pcg64Mcg::seed_from_u64(11);
    for hf in [
        fixture("jacksboro_33x33"),
        fixture("camera_33x33"),
        synthetic(17, 11, 4),
        synthetic(2, 9, 5),
    ] {
        let mut ev = Evaluator::new(hf.clone());
        let mut state = MeshState::default();
        for density in [0.0, 0.02, 0.1, 0.3, 0.7, 1.0] {
            let kept = random_kept(hf.len(), density, &mut rng);
            let editable = ev.score_into(&kept, &mut state).unwrap();
            let once = ev.score(&kept).unwrap();
            assert_eq!(bits(editable), bits(once), "density {density}");
        }
    }
}

/// Scores random mutants (1–8 flips, corners excluded) of random meshes of `hf` with
/// [`Evaluator::score_mutant`], which leaves the base as it is, against fresh evaluations.
/// Returns (mutants scored, mutants refused).
fn mutant_scores(hf: Arc<Heightfield>, seed: u64, rounds: usize) -> (usize, usize) {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut ev = Evaluator::new(hf.clone());
    let n = hf.len();
    let corners = hf.corners();
    let (mut scored, mut refused) = (0, 0);
    for round in 0..rounds {
        let density = [0.02, 0.1, 0.3, 0.7, 1.0][rng.random_range(0..5)];
        let kept = random_kept(n, density, &mut rng);
        let mut base = MeshState::default();
        ev.score_into(&kept, &mut base).unwrap();
        base.ensure_discs();
        let before = base.score().unwrap();
        for _ in 0..8 {
            let flips = rng.random_range(1..=8);
            let mut flip: Vec<u32> = Vec::new();
            while flip.len() < flips.min(n - 4) {
                let i = rng.random_range(0..n as u32);
                if !corners.contains(&i) && !flip.contains(&i) {
                    flip.push(i);
                }
            }
            let (removed, inserted) = as_edit(&base, flip);
            let changes = Changes {
                removed: &removed,
                inserted: &inserted,
            };
            let Some(score) = ev.score_mutant(&base, changes) else {
                refused += 1;
                continue;
            };
            scored += 1;
            let mutant: Vec<u32> = (0..n as u32)
                .filter(|&i| base.is_kept(i) != (removed.contains(&i) || inserted.contains(&i)))
                .collect();
            let fresh = ev.evaluate(&mutant).unwrap();
            assert_eq!(
                bits(score),
                bits(fresh.score),
                "{}×{} seed {seed} round {round} (−{removed:?} +{inserted:?})",
                hf.width(),
                hf.height(),
            );
        }
        assert_eq!(
            bits(base.score().unwrap()),
            bits(before),
            "the base is unchanged"
        );
    }
    (scored, refused)
}

#[test]
fn mutants_scored_without_a_copy_match_fresh_evaluation() {
    // Synthetic grids with exact ties and odd shapes (a mutant of a sparse mesh on a tiny grid
    // may drop every triangle, and is then built from scratch): none refused.
    for (w, h) in [(3, 3), (5, 4), (2, 7), (9, 9), (17, 11)] {
        for seed in 0..4 {
            let (scored, refused) = mutant_scores(synthetic(w, h, seed), seed, 12);
            assert_eq!((scored, refused), (96, 0), "{w}×{h} seed {seed}");
        }
    }
    // Real data: none refused.
    for (name, seed) in [
        ("jacksboro_33x33", 1),
        ("volcano_33x33", 2),
        ("camera_33x33", 3),
    ] {
        let (scored, refused) = mutant_scores(fixture(name), seed, 20);
        assert_eq!((scored, refused), (160, 0), "{name}");
    }
}

#[test]
fn a_mutant_that_is_not_one_is_refused() {
    // A corner cannot be removed, a kept point cannot be inserted, nor a point that the base
    // does not keep removed: each is refused rather than scored as something else.
    let hf = synthetic(5, 5, 1);
    let mut ev = Evaluator::new(hf.clone());
    let mut base = MeshState::default();
    ev.score_into(&[0, 4, 6, 12, 18, 20, 24], &mut base)
        .unwrap();
    base.ensure_discs();
    let refused = |removed: &[u32], inserted: &[u32], ev: &mut Evaluator| {
        let changes = Changes { removed, inserted };
        ev.score_mutant(&base, changes).is_none()
    };
    assert!(refused(&[0], &[], &mut ev), "a corner removed");
    assert!(refused(&[], &[12], &mut ev), "a kept point inserted");
    assert!(refused(&[13], &[], &mut ev), "a point not kept removed");
    assert!(refused(&[], &[25], &mut ev), "out of range");
    assert!(!refused(&[12], &[13], &mut ev), "a real mutant");
}

#[test]
fn every_single_removal_and_insertion_finds_the_largest_error_left() {
    // A mutant that drops the triangle holding E_max must find the largest error among the
    // triangles it keeps: exhaustive single-point mutants, on integer heights (many triangles
    // tie at the maximum) and on real ones (one triangle holds it), with meshes of more
    // triangles than the mesh keeps maxima for and of fewer.
    for (hf, density) in [
        (synthetic(17, 13, 2), 0.15),
        (synthetic(17, 13, 3), 0.15),
        (synthetic(9, 9, 2), 0.05),
        (fixture("volcano_33x33"), 0.06),
    ] {
        let mut rng = Pcg64Mcg::seed_from_u64(11);
        let mut ev = Evaluator::new(hf.clone());
        let n = hf.len() as u32;
        let corners = hf.corners();
        let mut kept = random_kept(hf.len(), density, &mut rng);
        kept.extend(corners);
        kept.sort_unstable();
        kept.dedup();
        let mut base = MeshState::default();
        ev.score_into(&kept, &mut base).unwrap();
        base.ensure_lookups();
        for p in (0..n).filter(|p| !corners.contains(p)) {
            let (removed, inserted) = as_edit(&base, [p]);
            let changes = Changes {
                removed: &removed,
                inserted: &inserted,
            };
            let score = ev
                .score_mutant(&base, changes)
                .expect("a single flip is scored");
            let mutant: Vec<u32> = (0..n).filter(|&i| base.is_kept(i) != (i == p)).collect();
            let fresh = ev.evaluate(&mutant).unwrap();
            assert_eq!(
                bits(score),
                bits(fresh.score),
                "{}×{} flip {p}",
                hf.width(),
                hf.height()
            );
        }
    }
}
