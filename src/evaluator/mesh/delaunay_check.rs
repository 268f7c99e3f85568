//! A check that a triangulation of grid points made elsewhere is Delaunay, for meshes the
//! evaluator scores on their own triangles.

use crate::evaluator::exact::predicates::{Lattice, in_circle_det, orient};

/// Whether a valid triangulation of grid points (as [`Evaluator::score_triangulation`](crate::evaluator::Evaluator::score_triangulation)
/// accepts) is Delaunay: every interior edge is locally Delaunay (the far vertex of one
/// triangle is not strictly inside the other's circumcircle), which for a triangulation makes
/// it Delaunay everywhere. Co-circular ties count as Delaunay whichever diagonal they take.
pub(crate) fn is_delaunay(tris: &[[u32; 3]], width: usize) -> bool {
    let lattice = Lattice::new(width);
    let p = |i: u32| lattice.point(i);
    // Each directed edge of a counter-clockwise triangle, with the triangle's third vertex.
    let mut edges: Vec<((u32, u32), u32)> = Vec::with_capacity(3 * tris.len());
    for &[a, b, c] in tris {
        let [a, b, c] = if orient(p(a), p(b), p(c)) > 0 {
            [a, b, c]
        } else {
            [a, c, b]
        };
        edges.extend([((a, b), c), ((b, c), a), ((c, a), b)]);
    }
    edges.sort_unstable();
    edges.iter().all(
        |&((a, b), c)| match edges.binary_search_by_key(&(b, a), |e| e.0) {
            Ok(k) => in_circle_det([p(a), p(b), p(c), p(edges[k].1)]) <= 0,
            Err(_) => true,
        },
    )
}
