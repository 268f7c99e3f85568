//! The evaluator against the paper's E computed by brute force, on real grids; `compose` and
//! `incremental` check composed children and edited meshes against fresh evaluation.

mod compose;
mod incremental;

use super::Evaluator;
use super::exact::paper_e;
use super::test_grids::{fixture, random_subset};
use rand::SeedableRng;
use std::sync::Arc;

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
                let (sum, max, sum_sq, missing) = paper_e::brute_force(&hf, &kept, &e.triangles);
                assert_eq!(missing, 0, "{name}: every grid point lies in some triangle");
                assert_close(e.score.e_sum, sum, name);
                assert_close(e.score.e_max, max, name);
                assert_close(e.score.rms, (sum_sq / hf.len() as f64).sqrt(), name);
            }
        }
    }
}
