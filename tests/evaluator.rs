//! The evaluator against a brute-force reference and hand-made grids with known answers.

use paretomesh::evaluator::{EvaluateError, Evaluator, reference, triangulation::Triangulation};
use paretomesh::heightfield::{self, Heightfield};
use rand::{RngExt, SeedableRng};
use std::path::Path;
use std::sync::Arc;

fn fixture(name: &str) -> Heightfield {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(format!("{name}.f32"));
    heightfield::load(&path).unwrap()
}

fn random_subset(n: usize, fraction: f64, rng: &mut rand_pcg::Pcg64Mcg) -> Vec<u32> {
    (0..n as u32)
        .filter(|_| rng.random::<f64>() < fraction)
        .collect()
}

fn assert_close(fast: f64, slow: f64, what: &str) {
    let tol = 1e-9 * slow.abs().max(1e-300);
    assert!(
        (fast - slow).abs() <= tol,
        "{what}: fast {fast} vs brute force {slow}"
    );
}

#[test]
fn matches_brute_force_on_random_subsets_of_real_data() {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(2024);
    for name in [
        "jacksboro_33x33",
        "camera_33x33",
        "bunny_33x33",
        "volcano_33x33",
    ] {
        let hf = fixture(name);
        let mut ev = Evaluator::new(Arc::new(hf.clone()));
        for fraction in [0.0, 0.02, 0.1, 0.3, 0.7] {
            for _ in 0..4 {
                let kept = random_subset(hf.len(), fraction, &mut rng);
                let e = ev.evaluate(&kept).unwrap();
                let (sum, max, sum_sq, missing) = reference::brute_force(&hf, &kept, &e.triangles);
                assert_eq!(missing, 0, "{name}: every grid point lies in some triangle");
                assert_close(e.score.e_sum, sum, name);
                assert_close(e.score.e_max, max, name);
                assert_close(e.score.rms, (sum_sq / hf.len() as f64).sqrt(), name);
            }
        }
    }
}

/// Every grid point that is not a vertex is owned by exactly one triangle.
#[test]
fn every_point_is_counted_exactly_once() {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
    let hf = fixture("volcano_33x33");
    let mut ev = Evaluator::new(Arc::new(hf.clone()));
    for fraction in [0.0, 0.05, 0.3, 0.9] {
        let kept = random_subset(hf.len(), fraction, &mut rng);
        let e = ev.evaluate(&kept).unwrap();
        let grid = paretomesh::evaluator::raster::Grid {
            width: hf.width() as i64,
            height: hf.height() as i64,
            z: hf.z(),
        };
        let mut hits = vec![0u32; hf.len()];
        let w = hf.width() as i64;
        for t in &e.triangles {
            grid.for_each_point(t.map(|i| [i as i64 % w, i as i64 / w]), |i, _| hits[i] += 1);
        }
        for (i, &h) in hits.iter().enumerate() {
            let vertex = ev.kept().binary_search(&(i as u32)).is_ok();
            assert_eq!(h, u32::from(!vertex), "point {i} (vertex: {vertex})");
        }
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

use paretomesh::evaluator::incremental::canonical as rotate_min_first;

/// All triangles are counter-clockwise and proper, and there are 2n − h − 2 of them
/// (n vertices, h on the hull), as for any triangulation of a point set.
#[test]
fn triangle_count_follows_euler() {
    let hf = fixture("camera_33x33");
    let mut ev = Evaluator::new(Arc::new(hf.clone()));
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
    let kept = random_subset(hf.len(), 0.2, &mut rng);
    let e = ev.evaluate(&kept).unwrap();
    let w = hf.width() as u32;
    let on_hull =
        |i: u32| i % w == 0 || i % w == w - 1 || i / w == 0 || i / w == hf.height() as u32 - 1;
    let n = ev.kept().len();
    let h = ev.kept().iter().filter(|&&i| on_hull(i)).count();
    assert_eq!(e.score.t, 2 * n - h - 2);
}

fn plane(width: usize, height: usize, f: impl Fn(f64, f64) -> f64) -> Heightfield {
    let z = (0..width * height)
        .map(|i| f((i % width) as f64, (i / width) as f64))
        .collect();
    Heightfield::new(width, height, z).unwrap()
}

#[test]
fn a_flat_or_tilted_plane_has_no_error() {
    // Linear interpolation reproduces any plane, whatever is kept.
    for hf in [
        plane(7, 5, |_, _| 3.0),
        plane(7, 5, |x, y| 0.25 * x - 1.5 * y + 2.0),
    ] {
        let mut ev = Evaluator::new(Arc::new(hf.clone()));
        for kept in [vec![], vec![8, 16, 20], (0..35).collect()] {
            let s = ev.score(&kept).unwrap();
            assert!(s.e_sum.abs() < 1e-12 && s.e_max < 1e-12, "{s:?}");
        }
    }
}

#[test]
fn a_two_by_two_grid_is_two_triangles_and_exact() {
    // Only the corners: nothing left to interpolate.
    let hf = Heightfield::new(2, 2, vec![1.0, 5.0, -2.0, 7.0]).unwrap();
    let e = Evaluator::new(Arc::new(hf.clone())).evaluate(&[]).unwrap();
    assert_eq!((e.score.e_sum, e.score.t), (0.0, 2));
}

#[test]
fn a_single_bump_costs_its_height_until_kept() {
    // 5×5 zeros with a bump of 10 at the centre; the bump is the only error.
    let mut z = vec![0.0; 25];
    z[12] = 10.0;
    let hf = Heightfield::new(5, 5, z).unwrap();
    let mut ev = Evaluator::new(Arc::new(hf.clone()));
    let s = ev.score(&[]).unwrap();
    assert_eq!((s.e_sum, s.e_max, s.t), (10.0, 10.0, 2));
    assert_eq!(s.rms, (100.0f64 / 25.0).sqrt());
    // Keeping the bump spreads z̃ over its neighbours: the error is now where the bump is not.
    let s = ev.score(&[12]).unwrap();
    assert_eq!(s.t, 4);
    assert!(s.e_sum > 0.0);
    // Keeping the bump and its 8 neighbours makes the error exactly zero.
    let s = ev.score(&[6, 7, 8, 11, 12, 13, 16, 17, 18]).unwrap();
    assert_eq!(s.e_sum, 0.0);
}

#[test]
fn collinear_rows_are_triangulated_without_slivers() {
    // Keep a whole middle row: many collinear points, each must become a proper vertex.
    let hf = plane(9, 3, |x, y| (x * 0.7).sin() + y);
    let mut ev = Evaluator::new(Arc::new(hf.clone()));
    let row: Vec<u32> = (9..18).collect();
    let e = ev.evaluate(&row).unwrap();
    // 13 points: the 4 corners and the row's two ends lie on the hull (h = 6), the other 7 row
    // points are interior, so T = 2n − h − 2 = 18.
    assert_eq!(e.score.t, 18);
}

#[test]
fn out_of_range_indices_are_rejected() {
    let hf = plane(3, 3, |_, _| 0.0);
    let err = Evaluator::new(Arc::new(hf.clone()))
        .score(&[9])
        .unwrap_err();
    assert_eq!(err, EvaluateError::IndexOutOfRange { index: 9, len: 9 });
}

#[test]
fn any_valid_triangulation_can_be_scored() {
    // The other diagonal of a 2×2 cell: Delaunay would choose one, an outside tool the other.
    let hf = Heightfield::new(3, 3, vec![0.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    let mut ev = Evaluator::new(Arc::new(hf.clone()));
    let s = ev.score_triangulation(&[[0, 2, 8], [0, 8, 6]]).unwrap();
    // The centre lies on the diagonal 0–8: interpolated 0, error 4.
    assert_eq!((s.e_sum, s.t), (4.0, 2));
    let s = ev.score_triangulation(&[[0, 2, 6], [2, 8, 6]]).unwrap();
    assert_eq!((s.e_sum, s.t), (4.0, 2));
}

#[test]
fn invalid_triangulations_are_rejected_with_a_reason() {
    let hf = plane(3, 3, |_, _| 0.0);
    let mut ev = Evaluator::new(Arc::new(hf.clone()));
    // Only half the square.
    assert!(matches!(
        ev.score_triangulation(&[[0, 2, 8]]),
        Err(EvaluateError::OpenEdge { .. })
    ));
    // Collinear.
    assert!(matches!(
        ev.score_triangulation(&[[0, 1, 2]]),
        Err(EvaluateError::DegenerateTriangle { .. })
    ));
    // Overlap: both diagonals' triangles.
    assert!(matches!(
        ev.score_triangulation(&[[0, 2, 8], [0, 8, 6], [0, 2, 6]]),
        Err(EvaluateError::OverlappingEdge { .. })
    ));
}
