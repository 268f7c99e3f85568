//! The paper's E (eq. 2–4) by brute force: the reference the fast evaluator is tested against.
//!
//! For every grid point that is not a vertex, it searches *all* triangles for one that contains
//! the point (closed triangle, exact integer test) and interpolates there with barycentric
//! weights. It is O(N·T): use it on small grids only.

use super::predicates::orient;
use crate::heightfield::Heightfield;

/// (E_sum, E_max, Σ squared error, number of points found in no triangle) of `triangles` on `hf`,
/// computed by exhaustive search. `kept` points contribute zero.
pub(crate) fn brute_force(
    hf: &Heightfield,
    kept: &[u32],
    triangles: &[[u32; 3]],
) -> (f64, f64, f64, usize) {
    let w = hf.width() as i64;
    let p = |i: u32| [i as i64 % w, i as i64 / w];
    let mut is_kept = vec![false; hf.len()];
    for &k in kept.iter().chain(hf.corners().iter()) {
        is_kept[k as usize] = true;
    }
    let (mut sum, mut max, mut sum_sq, mut missing) = (0.0, 0.0f64, 0.0, 0);
    for (i, &z) in hf.z().iter().enumerate() {
        if is_kept[i] {
            continue;
        }
        let q = p(i as u32);
        let found = triangles.iter().find_map(|t| {
            let [a, b, c] = t.map(p);
            let area = orient(a, b, c);
            let (wa, wb, wc) = (orient(b, c, q), orient(c, a, q), orient(a, b, q));
            let inside = if area > 0 {
                wa >= 0 && wb >= 0 && wc >= 0
            } else {
                wa <= 0 && wb <= 0 && wc <= 0
            };
            inside.then(|| {
                let zs = t.map(|v| hf.z()[v as usize]);
                (wa as f64 * zs[0] + wb as f64 * zs[1] + wc as f64 * zs[2]) / area as f64
            })
        });
        match found {
            Some(zt) => {
                let d = (z - zt).abs();
                sum += d;
                sum_sq += d * d;
                max = max.max(d);
            }
            None => missing += 1,
        }
    }
    (sum, max, sum_sq, missing)
}
