//! Exact geometric predicates on grid points, and the project's Delaunay tie rule.
//!
//! Grid points have integer coordinates below [`MAX_SIDE`](crate::heightfield::MAX_SIDE) = 2¹⁴,
//! so every predicate here is exact in `i64`: coordinate differences are < 2¹⁴, lifted heights
//! < 2²⁹, the in-circle determinant < 2⁶⁰.
//!
//! # The tie rule
//! Subsets of a grid are full of co-circular quadruples (every grid square is one), so their
//! Delaunay triangulation is not unique. ParetoMesh makes it unique by *Simulation of Simplicity*
//! (Edelsbrunner & Mücke 1990) on the lifting map: point `i` is lifted to height
//! `x² + y² + δᵢ`, where the δ are positive infinitesimals with `δᵢ ≫ δⱼ` whenever index `i <
//! j`. The triangulation is then the projection of the lower convex hull of generic lifted points:
//! one triangulation per point set, whatever the insertion order, and Delaunay in the ordinary
//! sense (only co-circular ties are decided by the perturbation).

/// A grid point as integer (column, row) coordinates.
pub(crate) type GridPoint = [i64; 2];

/// Converts grid indices to coordinates without a division: `index / width` is computed as
/// `(index · m) >> 42` with `m = ⌈2⁴² / width⌉`, exact for every index of a grid within
/// [`MAX_POINTS`](crate::heightfield::MAX_POINTS) = 2²⁸ points and width up to 2¹⁴: the error
/// term index·(m − 2⁴²/width)/2⁴² < index/2⁴² ≤ 2⁻¹⁴ stays below the 1/width gap, and
/// index·m < height·2⁴² + index ≤ 2⁵⁶ + 2²⁸ fits in `u64`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lattice {
    width: u64,
    magic: u64,
}

impl Lattice {
    /// Coordinates on a grid `width` columns wide.
    pub fn new(width: usize) -> Self {
        let width = width.max(1) as u64;
        Self {
            width,
            magic: (1u64 << 42).div_ceil(width),
        }
    }

    /// The grid's width.
    pub fn width(&self) -> usize {
        self.width as usize
    }

    /// (column, row) of a grid index.
    #[inline]
    pub fn point(&self, index: u32) -> GridPoint {
        let row = (index as u64 * self.magic) >> 42;
        [(index as u64 - row * self.width) as i64, row as i64]
    }
}

/// Twice the signed area of triangle (a, b, c): positive when a → b → c turns counter-clockwise
/// (x to the right, y up), zero when collinear.
#[inline]
pub(crate) fn orient(a: GridPoint, b: GridPoint, c: GridPoint) -> i64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The coefficients of the in-circle determinant as a linear function of the lifted heights.
///
/// Returns `(det, [ca, cb, cc, cd])`: `det > 0` iff `d` lies strictly inside the circle through
/// the counter-clockwise triangle `(a, b, c)`, and `cᵢ` is how `det` changes per unit of extra
/// height on point `i` (so `cd = −orient(a, b, c)`, never zero for a proper triangle).
#[inline]
fn incircle_terms(a: GridPoint, b: GridPoint, c: GridPoint, d: GridPoint) -> (i64, [i64; 4]) {
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    let ma = bdx * cdy - bdy * cdx;
    let mb = adx * cdy - ady * cdx;
    let mc = adx * bdy - ady * bdx;
    let la = adx * adx + ady * ady;
    let lb = bdx * bdx + bdy * bdy;
    let lc = cdx * cdx + cdy * cdy;
    let det = la * ma - lb * mb + lc * mc;
    (det, [ma, -mb, mc, -(ma - mb + mc)])
}

/// Is `d` inside the circle through the counter-clockwise triangle `(a, b, c)`, with exact
/// co-circular ties broken by the project's tie rule (see the module docs)?
///
/// `ia..id` are the points' grid indices, which rank their perturbations. The answer is the same
/// for every labelling of the same quadrilateral: for an edge `(a, b)` shared by triangles
/// `(a, b, c)` and `(b, a, d)`, `incircle(a, b, c, d)` and `incircle(b, a, d, c)` agree.
#[inline]
pub(crate) fn in_circle(pts: [GridPoint; 4], ids: [u32; 4]) -> bool {
    // The determinant alone on the common path; the tie path computes the coefficients again
    // out of line. Why: with them in one function, the coefficients and ids were spilled to
    // the stack (for the indexed tie scan) before every test, ties or not.
    let det = in_circle_det(pts);
    if det != 0 {
        return det > 0;
    }
    in_circle_tie(pts, ids)
}

/// The in-circle determinant of [`in_circle`] before its tie rule: > 0 when `d` lies strictly
/// inside the circle through the counter-clockwise triangle `(a, b, c)`, 0 on it.
#[inline]
pub(crate) fn in_circle_det([a, b, c, d]: [GridPoint; 4]) -> i64 {
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    (adx * adx + ady * ady) * (bdx * cdy - bdy * cdx)
        - (bdx * bdx + bdy * bdy) * (adx * cdy - ady * cdx)
        + (cdx * cdx + cdy * cdy) * (adx * bdy - ady * bdx)
}

/// [`in_circle`] for co-circular points: the tie rule. (Not cold: at 30 % kept a good share
/// of the tests tie.)
#[inline(never)]
fn in_circle_tie(pts: [GridPoint; 4], ids: [u32; 4]) -> bool {
    let (det, coef) = incircle_terms(pts[0], pts[1], pts[2], pts[3]);
    debug_assert_eq!(det, 0);
    // The most significant perturbation (smallest index) with a non-zero coefficient decides.
    // `cd` is never zero, so there is one. The indices are distinct, so a scan for the smallest
    // index among the non-zero coefficients finds the same one as sorting would, without the
    // sort (grid subsets hit this branch on a large share of their edges).
    let mut best = 3;
    for k in 0..3 {
        if coef[k] != 0 && ids[k] < ids[best] {
            best = k;
        }
    }
    debug_assert!(
        coef[3] != 0,
        "the coefficient of d is -orient(a, b, c), non-zero for a proper triangle"
    );
    coef[best] > 0
}

/// The circle through a counter-clockwise triangle (a, b, c), as the in-circle determinant's
/// coefficients, to test many points against one circle: about a third of the work of
/// [`in_circle`] per point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Circle {
    a: GridPoint,
    cx: i64,
    cy: i64,
    cl: i64,
}

impl Circle {
    /// The circle through the counter-clockwise triangle `(a, b, c)`.
    #[inline]
    pub(crate) fn new(a: GridPoint, b: GridPoint, c: GridPoint) -> Self {
        let (bx, by) = (b[0] - a[0], b[1] - a[1]);
        let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
        let (lb, lc) = (bx * bx + by * by, cx * cx + cy * cy);
        Self {
            a,
            cx: by * lc - lb * cy,
            cy: bx * lc - lb * cx,
            cl: bx * cy - by * cx,
        }
    }

    /// The in-circle determinant of `d`: the same value as [`in_circle`]'s before its tie rule
    /// (> 0 strictly inside, 0 on the circle). Exact: with |coordinate differences| < 2¹⁴ the
    /// coefficients stay below 2⁴⁴ and the three products below 2⁵⁸.
    #[inline]
    pub(crate) fn det(&self, d: GridPoint) -> i64 {
        let (dx, dy) = (d[0] - self.a[0], d[1] - self.a[1]);
        -dx * self.cx + dy * self.cy - (dx * dx + dy * dy) * self.cl
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn circle_det_is_the_in_circle_determinant() {
        // Random quadruples on a 2¹⁴ grid (the limit the exactness bound is stated for) and on
        // a small grid (many co-circular ties): the one-circle form must give the very value the
        // full determinant gives, zero included.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x2545_f491);
        let mut next = |bound: i64| rng.random_range(0..bound);
        let mut ties = 0;
        for round in 0..20_000 {
            let side = if round % 2 == 0 { 1 << 14 } else { 5 };
            let mut p = [0; 4].map(|_| [next(side), next(side)]);
            let turn = orient(p[0], p[1], p[2]);
            if turn == 0 {
                continue;
            }
            if turn < 0 {
                p.swap(1, 2);
            }
            let (det, _) = incircle_terms(p[0], p[1], p[2], p[3]);
            assert_eq!(Circle::new(p[0], p[1], p[2]).det(p[3]), det, "{p:?}");
            ties += usize::from(det == 0);
        }
        assert!(ties > 100, "the small grid must exercise ties ({ties})");
    }

    #[test]
    fn lattice_matches_division_at_the_limits() {
        for width in [2usize, 3, 7, 65, 257, 1000, 4099, 16_384] {
            let lattice = Lattice::new(width);
            let n = (crate::heightfield::MAX_POINTS as u32)
                .min((width * crate::heightfield::MAX_SIDE) as u32);
            for i in (0..n).step_by(97).chain(n - 1000..n) {
                let w = width as u32;
                assert_eq!(
                    lattice.point(i),
                    [(i % w) as i64, (i / w) as i64],
                    "width {width} index {i}"
                );
            }
        }
    }

    #[test]
    fn orient_signs() {
        assert!(orient([0, 0], [1, 0], [0, 1]) > 0);
        assert!(orient([0, 0], [0, 1], [1, 0]) < 0);
        assert_eq!(orient([0, 0], [1, 1], [2, 2]), 0);
    }

    #[test]
    fn strict_inside_and_outside() {
        let (a, b, c) = ([0, 0], [4, 0], [0, 4]);
        assert!(in_circle([a, b, c, [1, 1]], [0, 1, 2, 3]));
        assert!(!in_circle([a, b, c, [9, 9]], [0, 1, 2, 3]));
    }

    /// The tie rule as its definition reads: sort the perturbations by index, the first with a
    /// non-zero coefficient decides.
    fn in_circle_by_sorting(pts: [GridPoint; 4], ids: [u32; 4]) -> bool {
        let (det, coef) = incircle_terms(pts[0], pts[1], pts[2], pts[3]);
        if det != 0 {
            return det > 0;
        }
        let mut order = [0usize, 1, 2, 3];
        order.sort_unstable_by_key(|&k| ids[k]);
        let first = order.into_iter().find(|&k| coef[k] != 0).unwrap();
        coef[first] > 0
    }

    #[test]
    fn tie_scan_agrees_with_the_sorted_definition() {
        // Every counter-clockwise triangle and fourth point on a 4×4 grid, under every ranking
        // of the four indices: co-circular quadruples (squares, rectangles, isosceles
        // trapezoids, points on the circle next to a vertex) are common there, so the tie
        // branch runs many times with every pattern of zero coefficients.
        let grid: Vec<GridPoint> = (0..16).map(|i| [i % 4, i / 4]).collect();
        let rankings = [
            [0, 1, 2, 3],
            [3, 2, 1, 0],
            [1, 3, 0, 2],
            [2, 0, 3, 1],
            [0, 3, 1, 2],
            [2, 1, 3, 0],
        ];
        let mut ties = 0;
        for a in 0..16 {
            for b in 0..16 {
                for c in 0..16 {
                    if orient(grid[a], grid[b], grid[c]) <= 0 {
                        continue;
                    }
                    for d in (0..16).filter(|&d| d != a && d != b && d != c) {
                        let pts = [grid[a], grid[b], grid[c], grid[d]];
                        ties += usize::from(incircle_terms(pts[0], pts[1], pts[2], pts[3]).0 == 0);
                        for ids in rankings {
                            assert_eq!(
                                in_circle(pts, ids),
                                in_circle_by_sorting(pts, ids),
                                "{pts:?} ranked {ids:?}"
                            );
                        }
                    }
                }
            }
        }
        assert!(ties > 1000, "only {ties} co-circular cases");
    }

    #[test]
    fn unit_square_tie_is_decided_the_same_from_both_sides() {
        // The four corners of a grid square are co-circular: exactly one diagonal must win, and
        // both triangles of the quadrilateral must agree on which.
        let p = [[0, 0], [1, 0], [1, 1], [0, 1]];
        let id = [0, 1, 11, 10];
        for diag in [(0usize, 2usize), (1, 3)] {
            let (a, b) = diag;
            let (c, d) = ((a + 1) % 4, (a + 3) % 4);
            // Triangle (a, c, b) is counter-clockwise ... edge a-b, opposite points c and d.
            let t1 = in_circle([p[b], p[a], p[c], p[d]], [id[b], id[a], id[c], id[d]]);
            let t2 = in_circle([p[a], p[b], p[d], p[c]], [id[a], id[b], id[d], id[c]]);
            assert_eq!(t1, t2, "diagonal {diag:?}");
        }
        // And the two diagonals disagree: one is legal, the other is not.
        let keep_02 = !in_circle([p[2], p[0], p[1], p[3]], [id[2], id[0], id[1], id[3]]);
        let keep_13 = !in_circle([p[3], p[1], p[2], p[0]], [id[3], id[1], id[2], id[0]]);
        assert_ne!(keep_02, keep_13);
    }
}
