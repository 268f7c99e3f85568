//! Composed children ([`Evaluator::compose`]) against fresh evaluation: the same triangles, the
//! same error at every grid point and the same score, bit for bit, for children of seeded
//! random parents cut by block masks like an orthogonal-array crossover's and by scattered
//! masks; and a composed mesh must edit and compose further like any other.

use crate::evaluator::canonical_set as triangle_set;
use crate::evaluator::test_grids::{
    bits, random_subset as random_kept, shared_fixture as fixture, synthetic,
};
use crate::evaluator::{Changes, Crossing, Evaluator, MeshState, PartClasses, PartScores};
use crate::heightfield::Heightfield;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;

/// A bitset over `n` points with the points of `from_b` set.
fn bitset(n: usize, mut from_b: impl FnMut(usize) -> bool) -> Vec<u64> {
    let mut words = vec![0u64; n.div_ceil(64)];
    for i in (0..n).filter(|&i| from_b(i)) {
        words[i / 64] |= 1 << (i % 64);
    }
    words
}

/// Rectangles `[x0, y0, x1, y1]` (half-open) from recursive bisection of the grid, as the
/// spatial blocks of OAX.
fn rectangles(w: usize, h: usize, blocks: usize, rng: &mut Pcg64Mcg) -> Vec<[usize; 4]> {
    let mut rects = vec![[0, 0, w, h]];
    while rects.len() < blocks {
        let at = rng.random_range(0..rects.len());
        let [x0, y0, x1, y1] = rects[at];
        if x1 - x0 >= y1 - y0 && x1 - x0 > 1 {
            let cut = rng.random_range(x0 + 1..x1);
            rects[at] = [x0, y0, cut, y1];
            rects.push([cut, y0, x1, y1]);
        } else if y1 - y0 > 1 {
            let cut = rng.random_range(y0 + 1..y1);
            rects[at] = [x0, y0, x1, cut];
            rects.push([x0, cut, x1, y1]);
        } else {
            break;
        }
    }
    rects
}

/// The bitset of the points of the rectangles whose bit of `levels` is set.
fn rectangles_mask(w: usize, h: usize, rects: &[[usize; 4]], levels: u32) -> Vec<u64> {
    bitset(w * h, |i| {
        let (x, y) = (i % w, i / w);
        rects.iter().enumerate().any(|(k, &[x0, y0, x1, y1])| {
            (levels >> k) & 1 == 1 && (x0..x1).contains(&x) && (y0..y1).contains(&y)
        })
    })
}

/// Rectangles from recursive bisection of the grid, each labelled B with probability ½ (as
/// the spatial blocks of OAX and one row of its array).
fn block_mask(w: usize, h: usize, blocks: usize, rng: &mut Pcg64Mcg) -> Vec<u64> {
    let rects = rectangles(w, h, blocks, rng);
    let levels = rng.random::<u32>();
    rectangles_mask(w, h, &rects, levels)
}

/// The error bits of every grid point of `state`.
fn error_bits(state: &MeshState) -> Vec<u64> {
    state.errors().iter().map(|e| e.to_bits()).collect()
}

/// A parent mesh ready to compose from (disc boxes filled) keeping `density` of the points.
fn parent(ev: &mut Evaluator, density: f64, rng: &mut Pcg64Mcg) -> MeshState {
    let mut s = MeshState::default();
    ev.score_into(&random_kept(ev.heightfield().len(), density, rng), &mut s)
        .unwrap();
    s.ensure_discs();
    s
}

/// A parent of a random density, from empty to full.
fn random_parent(ev: &mut Evaluator, rng: &mut Pcg64Mcg) -> MeshState {
    let densities = [0.0, 0.02, 0.1, 0.3, 0.7, 1.0];
    let density = densities[rng.random_range(0..densities.len())];
    parent(ev, density, rng)
}

/// Checks `state` against a fresh evaluation of its kept set: score, triangles, and the error
/// of every grid point.
fn assert_matches_fresh(ev: &mut Evaluator, state: &MeshState, what: &str) {
    let n = ev.heightfield().len();
    let kept: Vec<u32> = (0..n as u32).filter(|&i| state.is_kept(i)).collect();
    let mut fresh = MeshState::default();
    let score = ev.score_into(&kept, &mut fresh).unwrap();
    assert_eq!(bits(state.score().unwrap()), bits(score), "{what}: score");
    assert_eq!(
        triangle_set(&state.triangles()),
        triangle_set(&fresh.triangles()),
        "{what}: triangles"
    );
    assert_eq!(error_bits(state), error_bits(&fresh), "{what}: errors");
}

/// Composes children of random parents on `hf` and checks each, then edits it and composes
/// from it.
fn compose_children(hf: Arc<Heightfield>, seed: u64, rounds: usize) {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut ev = Evaluator::new(hf.clone());
    let (w, h, n) = (hf.width(), hf.height(), hf.len());
    let mut a = random_parent(&mut ev, &mut rng);
    for round in 0..rounds {
        let b = random_parent(&mut ev, &mut rng);
        let mask = if rng.random::<f64>() < 0.8 {
            block_mask(w, h, rng.random_range(1..9), &mut rng)
        } else {
            let p = rng.random::<f64>();
            bitset(n, |_| rng.random::<f64>() < p)
        };
        let mut child = MeshState::default();
        let what = format!("{w}×{h} seed {seed} round {round}");
        let score = ev.compose(&mut child, &a, &b, &mask);
        assert!(score.is_some(), "{what}: compose gave up");
        assert_eq!(score, child.score(), "{what}");
        assert_matches_fresh(&mut ev, &child, &what);
        // A composed mesh is linked and hinted like a built one: it edits, and composes again.
        let flips: Vec<u32> = (0..n as u32)
            .filter(|i| !hf.corners().contains(i) && rng.random::<f64>() < 3.0 / n as f64)
            .collect();
        let mut edited = child.clone();
        let (remove, insert): (Vec<u32>, Vec<u32>) =
            flips.iter().partition(|&&i| edited.is_kept(i));
        ev.edit(&mut edited, &remove, &insert).unwrap();
        assert_matches_fresh(&mut ev, &edited, &format!("{what}, edited"));
        a = if round % 2 == 0 { child } else { b };
    }
}

#[test]
fn composed_children_match_fresh_evaluation_on_synthetic_grids() {
    // Thin grids (every point on the border), odd shapes, integer heights (exact ties, many
    // co-circular points) and real heights.
    for (w, h) in [
        (2, 2),
        (2, 7),
        (7, 2),
        (3, 3),
        (5, 4),
        (9, 9),
        (17, 11),
        (30, 8),
    ] {
        for seed in 0..6 {
            compose_children(synthetic(w, h, seed), seed, 20);
        }
    }
}

#[test]
fn composed_children_match_fresh_evaluation_on_real_data() {
    for (name, seed) in [
        ("jacksboro_33x33", 1),
        ("volcano_33x33", 2),
        ("camera_33x33", 3),
        ("jacksboro_65x65", 4),
    ] {
        compose_children(fixture(name), seed, 25);
    }
}

#[test]
fn a_child_equal_to_a_parent_takes_all_its_triangles() {
    // All genes from A (an empty mask), or from B (a full one): every triangle of that parent
    // is taken and nothing is triangulated anew; the result is still the parent's mesh.
    let hf = fixture("jacksboro_33x33");
    let n = hf.len();
    let mut ev = Evaluator::new(hf.clone());
    let mut rng = Pcg64Mcg::seed_from_u64(5);
    let mut a = MeshState::default();
    let mut b = MeshState::default();
    ev.score_into(&random_kept(n, 0.2, &mut rng), &mut a)
        .unwrap();
    ev.score_into(&random_kept(n, 0.05, &mut rng), &mut b)
        .unwrap();
    let mut child = MeshState::default();
    assert_eq!(
        ev.compose(&mut child, &a, &b, &bitset(n, |_| false)),
        None,
        "parents without disc boxes are refused"
    );
    a.ensure_discs();
    b.ensure_discs();
    for (mask, parent) in [(bitset(n, |_| false), &a), (bitset(n, |_| true), &b)] {
        let score = ev.compose(&mut child, &a, &b, &mask).unwrap();
        assert_eq!(bits(score), bits(parent.score().unwrap()));
        assert_eq!(
            triangle_set(&child.triangles()),
            triangle_set(&parent.triangles())
        );
    }
}

/// Composes every child of random parents over random rectangles both ways, by parts and by
/// the equivalent bitset, and requires the same mesh (slot for slot) and bits; scores each
/// without a mesh too ([`Evaluator::score_parts`]), which must give the same bits.
fn compose_by_parts(
    hf: Arc<Heightfield>,
    seed: u64,
    rounds: usize,
    (mutants, refused): (&mut usize, &mut usize),
) {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut ev = Evaluator::new(hf.clone());
    let (w, h) = (hf.width(), hf.height());
    for round in 0..rounds {
        let (a, b) = (
            random_parent(&mut ev, &mut rng),
            random_parent(&mut ev, &mut rng),
        );
        let mut rects = rectangles(w, h, rng.random_range(1..9), &mut rng);
        if rng.random::<f64>() < 0.2 {
            // An empty block, as OAX makes when the grid has fewer points than factors.
            rects.insert(rng.random_range(0..=rects.len()), [0, 0, 0, 0]);
        }
        let classes = PartClasses::new(&hf, &a, &b, &rects).expect("the rectangles tile the grid");
        let mut scores = PartScores::default();
        let crossing = Crossing {
            hf: &hf,
            parents: [&a, &b],
            classes: &classes,
        };
        assert!(scores.prepare(crossing));
        let all = 1u32 << rects.len();
        let levels: Vec<u32> = if all <= 16 {
            (0..all).collect()
        } else {
            (0..12).map(|_| rng.random_range(0..all)).collect()
        };
        for (k, &level) in levels.iter().enumerate() {
            let what = format!("{w}×{h} seed {seed} round {round} levels {level:b}");
            let mut by_parts = MeshState::default();
            let mut by_bits = MeshState::default();
            let score = ev.compose_parts(&mut by_parts, &a, &b, &classes, level);
            assert!(score.is_some(), "{what}: gave up");
            let mask = rectangles_mask(w, h, &rects, level);
            assert_eq!(score, ev.compose(&mut by_bits, &a, &b, &mask), "{what}");
            // Scored without a mesh: the same bits.
            let scored = ev.score_parts(&a, &b, &classes, &mut scores, level);
            assert_eq!(scored.map(bits), score.map(bits), "{what}: score_parts");
            assert_eq!(by_parts.triangles(), by_bits.triangles(), "{what}");
            assert_eq!(error_bits(&by_parts), error_bits(&by_bits), "{what}");
            if k < 3 {
                assert_matches_fresh(&mut ev, &by_parts, &what);
            }
            // A mutant of the child (1–6 points flipped, anywhere: inside a block, on a seam,
            // on the grid border), scored without a mesh: its fresh score's bits.
            let n = hf.len() as u32;
            let mut flips: Vec<u32> = (0..rng.random_range(1..7))
                .map(|_| rng.random_range(0..n))
                .filter(|i| !hf.corners().contains(i))
                .collect();
            flips.sort_unstable();
            flips.dedup();
            let (removed, inserted): (Vec<u32>, Vec<u32>) =
                flips.iter().partition(|&&i| by_parts.is_kept(i));
            let changes = Changes {
                removed: &removed,
                inserted: &inserted,
            };
            let mutant = ev.score_parts_changed(&a, &b, &classes, &mut scores, level, changes);
            let kept: Vec<u32> = (0..n)
                .filter(|&i| by_parts.is_kept(i) != flips.contains(&i))
                .collect();
            let fresh = ev.score(&kept).unwrap();
            *mutants += 1;
            match mutant {
                Some(s) => assert_eq!(bits(s), bits(fresh), "{what}: mutant {flips:?}"),
                None => *refused += 1,
            }
        }
    }
}

#[test]
fn children_composed_by_parts_equal_those_composed_by_bitset() {
    let (mut mutants, mut refused) = (0, 0);
    for (w, h) in [(2, 2), (2, 7), (7, 2), (5, 4), (9, 9), (17, 11), (30, 8)] {
        for seed in 0..4 {
            let counts = (&mut mutants, &mut refused);
            compose_by_parts(synthetic(w, h, seed), 40 + seed, 8, counts);
        }
    }
    for (name, seed) in [
        ("jacksboro_33x33", 1),
        ("camera_33x33", 3),
        ("jacksboro_65x65", 4),
    ] {
        compose_by_parts(fixture(name), seed, 10, (&mut mutants, &mut refused));
    }
    // No mutant is refused: a guard that fails means R was made wrong (a child that reuses
    // nothing, or whose changes drop all it reuses, is built from scratch instead).
    assert!(mutants > 2000, "{mutants} mutants");
    assert_eq!(refused, 0, "{refused} of {mutants} mutants refused");
}

#[test]
fn a_part_classification_serves_only_its_parents_and_tilings() {
    let hf = fixture("jacksboro_33x33");
    let (w, h, n) = (hf.width(), hf.height(), hf.len());
    let mut ev = Evaluator::new(hf.clone());
    let mut rng = Pcg64Mcg::seed_from_u64(9);
    let mut states: Vec<MeshState> = (0..3).map(|_| parent(&mut ev, 0.2, &mut rng)).collect();
    let halves = [[0, 0, w / 2, h], [w / 2, 0, w, h]];
    // Rectangles that overlap, leave a gap, or leave the grid are not a tiling.
    for bad in [
        vec![[0, 0, w / 2 + 1, h], [w / 2, 0, w, h]],
        vec![[0, 0, w / 2, h], [w / 2 + 1, 0, w, h]],
        vec![[0, 0, w / 2, h], [w / 2, 0, w + 1, h]],
    ] {
        assert!(PartClasses::new(&hf, &states[0], &states[1], &bad).is_none());
    }
    let too_many: Vec<[usize; 4]> = (0..33).map(|x| [x, 0, x + 1, h]).collect();
    assert!(PartClasses::new(&hf, &states[0], &states[1], &too_many).is_none());
    let classes = PartClasses::new(&hf, &states[0], &states[1], &halves).unwrap();
    // Scores prepared from one classification serve that one only, even for the same parents
    // (the weighted-sum GA crosses the same pair again with other blocks).
    let mut scores = PartScores::default();
    let crossing = Crossing {
        hf: &hf,
        parents: [&states[0], &states[1]],
        classes: &classes,
    };
    assert!(scores.prepare(crossing));
    let thirds = [[0, 0, w / 3, h], [w / 3, 0, w, h]];
    let other_classes = PartClasses::new(&hf, &states[0], &states[1], &thirds).unwrap();
    assert!(
        ev.score_parts(&states[0], &states[1], &other_classes, &mut scores, 0b10)
            .is_none()
    );
    assert!(
        ev.score_parts(&states[0], &states[1], &classes, &mut scores, 0b10)
            .is_some()
    );
    let mut child = MeshState::default();
    assert!(
        ev.compose_parts(&mut child, &states[0], &states[1], &classes, 0b10)
            .is_some()
    );
    // Other parents, the parents swapped, or a parent changed since: refused.
    assert!(
        ev.compose_parts(&mut child, &states[0], &states[2], &classes, 0b10)
            .is_none()
    );
    assert!(
        ev.compose_parts(&mut child, &states[1], &states[0], &classes, 0b10)
            .is_none()
    );
    let inserted = (0..n as u32).find(|&i| !states[1].is_kept(i)).unwrap();
    ev.edit(&mut states[1], &[], &[inserted]).unwrap();
    states[1].ensure_discs();
    assert!(
        ev.compose_parts(&mut child, &states[0], &states[1], &classes, 0b10)
            .is_none()
    );
    assert!(
        ev.score_parts(&states[0], &states[1], &classes, &mut scores, 0b10)
            .is_none()
    );
}
