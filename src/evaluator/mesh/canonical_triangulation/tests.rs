//! The canonical triangulation against spade, against its step-by-step reading, and under
//! every insertion order.

use super::*;
use crate::evaluator::mesh::canonical_form::canonical as rotate_min_first;
use crate::evaluator::test_grids::random_subset;
use rand::{RngExt, SeedableRng};

/// [`Triangulation::insert_all`] as it reads with `walk` and `insert_point` on the half-edge
/// arrays (the points in the same order and directions).
fn insert_all_by_steps(mesh: &mut Triangulation, width: usize, kept: &[u32]) {
    let lattice = Lattice::new(width);
    let points: Vec<GridPoint> = kept.iter().map(|&i| lattice.point(i)).collect();
    let x0 = points.iter().map(|p| p[0]).min().unwrap();
    let x1 = points.iter().map(|p| p[0]).max().unwrap();
    let y0 = points.iter().map(|p| p[1]).min().unwrap();
    let y1 = points.iter().map(|p| p[1]).max().unwrap();
    let index = |x: i64, y: i64| (y * width as i64 + x) as u32;
    let [a, b, c, d] = [index(x0, y0), index(x1, y0), index(x1, y1), index(x0, y1)];
    mesh.lattice = lattice;
    mesh.vertices = vec![a, b, c, c, d, a];
    mesh.twin = vec![NONE, NONE, 5, NONE, NONE, 2];
    let _ = mesh.flip_if_illegal(2);
    let mut plan = InsertionOrder::default();
    let (order, groups) = plan.plan(lattice, kept, [x0, y0, x1, y1]);
    let (mut last, mut stack) = (0, Vec::new());
    for (k, &(start, end)) in groups.iter().enumerate() {
        let mut group = order[start as usize..end as usize].to_vec();
        if k % 2 == 1 {
            group.reverse();
        }
        for p in group {
            if [a, b, c, d].contains(&p) {
                continue;
            }
            let t = mesh.walk(last, lattice.point(p), mesh.walk_cap()).unwrap();
            if !mesh.triangle(t as usize).contains(&p) {
                last = mesh.insert_point(t, p, &mut stack, |_| {});
            }
        }
    }
}

#[test]
fn insertion_on_halves_takes_the_same_steps() {
    // Random subsets (sparse to full, with repeats and points on the box's border) of grids
    // and of boxes inside them: the same slots, rotations and links, not only the same
    // triangles.
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x7a11);
    for round in 0..300 {
        let (w, h) = (
            2 + rng.random_range(0..40usize),
            2 + rng.random_range(0..40usize),
        );
        let fraction = [0.02, 0.1, 0.3, 0.8, 1.0][round % 5];
        let (x0, y0) = (rng.random_range(0..w / 2), rng.random_range(0..h / 2));
        let (x1, y1) = (rng.random_range(x0 + 1..w), rng.random_range(y0 + 1..h));
        let mut kept: Vec<u32> = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
            .iter()
            .map(|&(x, y)| (y * w + x) as u32)
            .collect();
        for y in y0..=y1 {
            for x in x0..=x1 {
                if rng.random::<f64>() < fraction {
                    kept.push((y * w + x) as u32);
                }
            }
        }
        kept.sort_unstable();
        if round % 7 == 0 {
            kept.push(kept[kept.len() / 2]);
            kept.sort_unstable();
        }
        let mut fast = Triangulation::default();
        assert!(fast.insert_all(w, &kept));
        let mut steps = Triangulation::default();
        insert_all_by_steps(&mut steps, w, &kept);
        assert_eq!(fast.vertices, steps.vertices, "round {round}");
        assert_eq!(fast.twin, steps.twin, "round {round}");
    }
}

#[test]
fn insertion_order_takes_every_point_once_by_rows_or_by_bands() {
    // A dense set goes row by row: each group one row of `kept`, rounds y ≡ 0, 2, then odd
    // (mod 4). A sparse one goes by bands: each group one band of rows in one round, its
    // cells left to right, and row order kept within a cell. Either way every point (repeats
    // included) comes exactly once.
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x0bde);
    let (w, h) = (257usize, 200usize);
    let lattice = Lattice::new(w);
    // The band (log₂ of the cell side) each density gets: cells of about four points.
    for (fraction, band) in [(0.02, Some(4)), (0.05, Some(3)), (0.3, None), (1.0, None)] {
        let mut kept: Vec<u32> = (0..(w * h) as u32)
            .filter(|_| rng.random::<f64>() < fraction)
            .collect();
        kept.push(kept[kept.len() / 3]);
        kept.sort_unstable();
        let mut plan = InsertionOrder::default();
        let (points, groups) = plan.plan(lattice, &kept, [0, 0, w as i64 - 1, h as i64 - 1]);
        let mut sequence: Vec<u32> = groups
            .iter()
            .flat_map(|&(s, e)| points[s as usize..e as usize].iter().copied())
            .collect();
        assert_eq!(sequence.len(), kept.len(), "{fraction}");
        let round = |p: u32| InsertionOrder::round_of(lattice.point(p)[1]);
        let rounds: Vec<usize> = sequence.iter().map(|&p| round(p)).collect();
        assert!(rounds.is_sorted(), "{fraction}: rounds in order");
        let rows_of = |&(s, e): &(u32, u32)| -> Vec<i64> {
            let mut ys: Vec<i64> = points[s as usize..e as usize]
                .iter()
                .map(|&p| lattice.point(p)[1])
                .collect();
            ys.dedup();
            ys
        };
        if let Some(band) = band {
            assert!(groups.windows(2).all(|g| g[0].1 == g[1].0), "{fraction}");
            for g in groups {
                let ys = rows_of(g);
                let bands: Vec<i64> = ys.iter().map(|y| y >> band).collect();
                assert!(bands.iter().all(|&b| b == bands[0]), "{fraction}: one band");
            }
            assert!(
                groups.iter().any(|g| rows_of(g).len() > 1),
                "{fraction}: a group spans several rows"
            );
            for &(s, e) in groups {
                let xs: Vec<i64> = points[s as usize..e as usize]
                    .iter()
                    .map(|&p| lattice.point(p)[0] >> band)
                    .collect();
                assert!(xs.is_sorted(), "{fraction}: cells left to right");
            }
        } else {
            assert!(groups.iter().all(|g| rows_of(g).len() == 1), "{fraction}");
        }
        sequence.sort_unstable();
        assert_eq!(sequence, kept, "{fraction}: every point once");
    }
}

/// The triangulation depends on the point set only, not on the order it is given in.
#[test]
fn triangulation_ignores_insertion_order() {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(9);
    // A 9×9 grid with every point kept is full of co-circular squares: a stress test for ties.
    let width = 9;
    for fraction in [1.0, 0.5, 0.25] {
        let mut kept: Vec<u32> = random_subset(81, fraction, &mut rng);
        kept.extend([0, 8, 72, 80]);
        kept.sort_unstable();
        kept.dedup();
        let mut canonical = Triangulation::default();
        canonical.rebuild_delaunay(width, &kept);
        let mut expected = canonical
            .triangles()
            .into_iter()
            .map(rotate_min_first)
            .collect::<Vec<_>>();
        expected.sort_unstable();
        for _ in 0..5 {
            let mut shuffled = kept.clone();
            for i in (1..shuffled.len()).rev() {
                shuffled.swap(i, rng.random_range(0..=i));
            }
            let mut t = Triangulation::default();
            t.rebuild_delaunay(width, &shuffled);
            let mut got = t
                .triangles()
                .into_iter()
                .map(rotate_min_first)
                .collect::<Vec<_>>();
            got.sort_unstable();
            assert_eq!(got, expected, "fraction {fraction}");
        }
    }
}

/// Lawson insertion ([`Triangulation::insert_all`], what the evaluator uses) and spade's bulk
/// load with legalisation ([`Triangulation::rebuild_with_spade`]) are independent algorithms:
/// they must give the same canonical triangles on every point set, from sparse to the full grid
/// (full of co-circular squares), with points on the box's border, and on a box smaller than the
/// grid. Without the box's four corners, `insert_all` declines and the spade path is taken.
#[test]
fn insertion_and_spade_build_the_same_triangulation() {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(21);
    let canonical = |t: &Triangulation| {
        let mut v: Vec<_> = t.triangles().into_iter().map(rotate_min_first).collect();
        v.sort_unstable();
        v
    };
    for (width, height) in [(2usize, 2usize), (9, 9), (17, 5), (33, 33), (65, 40)] {
        let n = width * height;
        for fraction in [0.0, 0.03, 0.1, 0.3, 0.7, 1.0] {
            // The whole grid's box, then a box from (1, 1) to (width − 2, height − 1) when the
            // grid is big enough: its corners kept, only points inside it.
            let mut boxes = vec![(0, 0, width - 1, height - 1)];
            if width > 3 && height > 3 {
                boxes.push((1, 1, width - 2, height - 1));
            }
            for (x0, y0, x1, y1) in boxes {
                let inside = |i: u32| {
                    let (x, y) = (i as usize % width, i as usize / width);
                    (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
                };
                let mut kept: Vec<u32> = random_subset(n, fraction, &mut rng)
                    .into_iter()
                    .filter(|&i| inside(i))
                    .collect();
                kept.extend(
                    [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| (y * width + x) as u32),
                );
                kept.sort_unstable();
                kept.dedup();
                let (mut by_insertion, mut by_spade) =
                    (Triangulation::default(), Triangulation::default());
                assert!(by_insertion.insert_all(width, &kept));
                by_spade.rebuild_with_spade(width, &kept);
                assert_eq!(
                    canonical(&by_insertion),
                    canonical(&by_spade),
                    "{width}×{height}, {fraction} kept, box {:?}",
                    (x0, y0, x1, y1)
                );
                // A repeated point changes nothing.
                if let Some(&again) = kept.get(kept.len() / 2) {
                    let mut repeated = kept.clone();
                    repeated.push(again);
                    let mut with_repeat = Triangulation::default();
                    assert!(with_repeat.insert_all(width, &repeated));
                    assert_eq!(canonical(&with_repeat), canonical(&by_spade));
                }
                // Without a corner of its box the set is refused, and rebuild_delaunay falls
                // back to spade.
                if kept.len() > 4 {
                    let without = &kept[1..];
                    assert!(!by_insertion.insert_all(width, without));
                    by_insertion.rebuild_delaunay(width, without);
                    by_spade.rebuild_with_spade(width, without);
                    assert_eq!(canonical(&by_insertion), canonical(&by_spade));
                }
            }
        }
    }
}
