//! Delaunay re-triangulation of the hole left by removing one vertex.
//!
//! Removing vertex v from a Delaunay triangulation leaves a star-shaped hole whose new triangles
//! are exactly the Delaunay triangles of the hole's boundary vertices that lie inside the hole
//! (also under the project's tie rule, which is a consistent perturbation of the lifting map).
//! Ear clipping finds them in O(k²) per ear: an ear (a, b, c) of the remaining polygon is clipped
//! when it turns counter-clockwise and no boundary vertex lies in its circumcircle under
//! [`predicates::in_circle`]. Such an ear is a Delaunay triangle of the boundary set and, being an
//! ear, inside the hole; one always exists because the hole's Delaunay triangulation has ears.
//! Each candidate's circle is set up once ([`Circle`]) and tested against the boundary's points,
//! converted from grid indices once per hole, since hole fills are a large share of an edit.

use crate::evaluator::exact::predicates::{self, Circle, GridPoint, Lattice};

/// Triangulates the counter-clockwise polygon `boundary` (grid indices on `lattice`,
/// at least 3) into the Delaunay triangles of its vertices that lie inside it, appended to `out`
/// counter-clockwise. Returns false (and leaves `out` as it was) when no empty ear exists, which
/// only happens if `boundary` is not the hole of a Delaunay vertex removal.
pub(crate) fn fill(boundary: &[u32], lattice: Lattice, out: &mut Vec<[u32; 3]>) -> bool {
    let start = out.len();
    let k = boundary.len();
    // The boundary's points, converted once, and the polygon left to clip as positions in it:
    // on the stack for the usual small holes (no allocation per removal), else on the heap.
    const SMALL: usize = 32;
    let (mut small_points, mut small_poly) = ([[0i64; 2]; SMALL], [0usize; SMALL]);
    let (mut large_points, mut large_poly) = (Vec::new(), Vec::new());
    let (points, mut poly): (&[GridPoint], &mut [usize]) = if k <= SMALL {
        for (j, &i) in boundary.iter().enumerate() {
            small_points[j] = lattice.point(i);
            small_poly[j] = j;
        }
        (&small_points[..k], &mut small_poly[..k])
    } else {
        large_points.extend(boundary.iter().map(|&i| lattice.point(i)));
        large_poly.extend(0..k);
        (&large_points[..], &mut large_poly[..])
    };
    // Ears before `from` were tested and failed; clipping changes only the two ears beside the
    // clipped vertex, and an ear's test (its turn, the whole boundary outside its circle) does
    // not change otherwise, so they still fail: the search resumes there and finds the same
    // first ear as a search from 0.
    let mut from = 0;
    while poly.len() > 3 {
        let n = poly.len();
        let ear = (from..n).find(|&e| {
            let (a, b, c) = (poly[(e + n - 1) % n], poly[e], poly[(e + 1) % n]);
            let (pa, pb, pc) = (points[a], points[b], points[c]);
            if predicates::orient(pa, pb, pc) <= 0 {
                return false;
            }
            // One circle against every other boundary vertex; exact ties (common on grids) go
            // to the tie rule.
            let circle = Circle::new(pa, pb, pc);
            (0..k).all(|d| {
                if d == a || d == b || d == c {
                    return true;
                }
                match circle.det(points[d]) {
                    0 => !predicates::in_circle(
                        [pa, pb, pc, points[d]],
                        [boundary[a], boundary[b], boundary[c], boundary[d]],
                    ),
                    det => det < 0,
                }
            })
        });
        let Some(e) = ear else {
            out.truncate(start);
            return false;
        };
        out.push([poly[(e + n - 1) % n], poly[e], poly[(e + 1) % n]].map(|j| boundary[j]));
        poly.copy_within(e + 1.., e);
        poly = &mut poly[..n - 1];
        // The ears at e − 1 and e changed; clipping the last vertex changes the first ear.
        from = if e == n - 1 { 0 } else { e.saturating_sub(1) };
    }
    if predicates::orient(points[poly[0]], points[poly[1]], points[poly[2]]) <= 0 {
        out.truncate(start);
        return false;
    }
    out.push([poly[0], poly[1], poly[2]].map(|j| boundary[j]));
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_hole_takes_the_tie_rule_diagonal() {
        // The 4 corners of a unit square on a 10-wide grid are co-circular: the fill must pick
        // the diagonal the tie rule picks, i.e. the one the evaluator's triangulation has.
        let (a, b, c, d) = (0u32, 1u32, 11u32, 10u32);
        let mut out = Vec::new();
        assert!(fill(&[a, b, c, d], Lattice::new(10), &mut out));
        assert_eq!(out.len(), 2);
        let mut mesh = crate::evaluator::mesh::canonical_triangulation::Triangulation::default();
        mesh.rebuild_delaunay(10, &[0, 1, 10, 11]);
        let canon = crate::evaluator::mesh::canonical_form::canonical_set;
        assert_eq!(canon(&out), canon(&mesh.triangles()));
    }

    #[test]
    fn reflex_vertex_is_never_an_ear() {
        // An arrow-shaped pentagon (reflex at (2,1)) on a 10-wide grid: every triangle must turn
        // counter-clockwise and together they must cover the polygon's area exactly.
        let p = |x: u32, y: u32| y * 10 + x;
        let poly = [p(0, 0), p(2, 1), p(4, 0), p(4, 3), p(0, 3)];
        let mut out = Vec::new();
        assert!(fill(&poly, Lattice::new(10), &mut out));
        assert_eq!(out.len(), 3);
        let pt = |i: u32| [i as i64 % 10, i as i64 / 10];
        let area: i64 = out
            .iter()
            .map(|t| predicates::orient(pt(t[0]), pt(t[1]), pt(t[2])))
            .inspect(|&o| assert!(o > 0))
            .sum();
        // Shoelace of the pentagon, doubled.
        assert_eq!(area, 4 * 3 * 2 - 4);
    }
}
