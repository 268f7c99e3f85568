//! The evaluator on hand-made grids with known answers, and its checks of bad input.

use paretomesh::evaluator::{EvaluateError, Evaluator};
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use rand::{RngExt, SeedableRng};
use std::path::Path;
use std::sync::Arc;

fn fixture(name: &str) -> Heightfield {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(format!("{name}.f32"));
    import::load(&path).unwrap()
}

fn random_subset(n: usize, fraction: f64, rng: &mut rand_pcg::Pcg64Mcg) -> Vec<u32> {
    (0..n as u32)
        .filter(|_| rng.random::<f64>() < fraction)
        .collect()
}

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
