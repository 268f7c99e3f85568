//! Exact rasterisation of one triangle over the grid, and the error it accumulates.
//!
//! A grid point belongs to a triangle when every edge function is non-negative, with the
//! **ownership rule** for points exactly on an edge: of the two directions of an edge, the one
//! pointing down (dy < 0), or right when horizontal (dy = 0, dx > 0), owns its points; an edge on
//! the grid border owns its points in either direction (it has no second triangle). So every
//! point on a shared edge falls in exactly one triangle. The triangle's own vertices are skipped:
//! they are kept points and their error is zero by definition.

use super::predicates::GridPoint;

/// Error sums over the points one triangle owns.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleError {
    /// Σ |z − z̃|.
    pub sum: f64,
    /// Σ (z − z̃)².
    pub sum_sq: f64,
    /// max |z − z̃|.
    pub max: f64,
    /// Number of grid points counted (vertices excluded).
    pub points: u32,
}

/// The grid a triangle is rasterised on.
pub struct Grid<'a> {
    /// Columns.
    pub width: i64,
    /// Rows.
    pub height: i64,
    /// Heights, row-major.
    pub z: &'a [f64],
}

impl Grid<'_> {
    #[inline]
    fn on_border(&self, a: GridPoint, b: GridPoint) -> bool {
        (a[0] == b[0] && (a[0] == 0 || a[0] == self.width - 1))
            || (a[1] == b[1] && (a[1] == 0 || a[1] == self.height - 1))
    }

    /// Visits every grid point the counter-clockwise triangle `tri` owns (vertices excluded) with
    /// its index and its interpolated height z̃.
    #[inline]
    pub fn for_each_point(&self, tri: [GridPoint; 3], mut visit: impl FnMut(usize, f64)) {
        let [a, b, c] = tri;
        let area = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) as f64;
        debug_assert!(area > 0.0, "triangle must be counter-clockwise and proper");
        let w = self.width as usize;
        let za = self.z[(a[1] as usize) * w + a[0] as usize];
        let zb = self.z[(b[1] as usize) * w + b[0] as usize];
        let zc = self.z[(c[1] as usize) * w + c[0] as usize];
        // Edge functions E(p) = A·x + B(y); the weight of a vertex is the edge opposite it.
        let edges = [(b, c, za), (c, a, zb), (a, b, zc)];
        let mut slope = [0i64; 3];
        let mut bias = [0i64; 3];
        for (k, &(p, q, _)) in edges.iter().enumerate() {
            slope[k] = p[1] - q[1];
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let owned = dy < 0 || (dy == 0 && dx > 0) || self.on_border(p, q);
            bias[k] = if owned { 0 } else { 1 };
        }
        let s1: f64 = (0..3).map(|k| slope[k] as f64 * edges[k].2).sum();
        let inv_area = 1.0 / area;
        let y_lo = a[1].min(b[1]).min(c[1]);
        let y_hi = a[1].max(b[1]).max(c[1]);
        let x_lo = a[0].min(b[0]).min(c[0]);
        let x_hi = a[0].max(b[0]).max(c[0]);
        for y in y_lo..=y_hi {
            let (mut lo, mut hi) = (x_lo, x_hi);
            let mut offset = [0i64; 3];
            for (k, &(p, q, _)) in edges.iter().enumerate() {
                // E(x, y) = (q.x − p.x)(y − p.y) − (q.y − p.y)(x − p.x) = slope·x + offset.
                offset[k] = (q[0] - p[0]) * (y - p[1]) + (q[1] - p[1]) * p[0];
                let need = bias[k] - offset[k]; // the point is owned iff slope·x ≥ need
                match slope[k] {
                    s if s > 0 => lo = lo.max(-floor_div(-need, s)),
                    s if s < 0 => hi = hi.min(floor_div(-need, -s)),
                    _ if need > 0 => hi = lo - 1,
                    _ => {}
                }
            }
            if lo > hi {
                continue;
            }
            let row = (y as usize) * w;
            // z̃(x) = (Σ E_k(x)·z_k) / area, and Σ E_k(x)·z_k is affine in x.
            let s0: f64 = (0..3)
                .map(|k| (slope[k] * lo + offset[k]) as f64 * edges[k].2)
                .sum();
            for x in lo..=hi {
                if (x == a[0] && y == a[1]) || (x == b[0] && y == b[1]) || (x == c[0] && y == c[1])
                {
                    continue;
                }
                let interpolated = (s0 + (x - lo) as f64 * s1) * inv_area;
                visit(row + x as usize, interpolated);
            }
        }
    }

    /// The error sums of the points triangle `tri` owns.
    pub fn triangle_error(&self, tri: [GridPoint; 3]) -> TriangleError {
        let mut acc = TriangleError::default();
        self.for_each_point(tri, |i, zt| {
            let d = (self.z[i] - zt).abs();
            acc.sum += d;
            acc.sum_sq += d * d;
            acc.max = acc.max.max(d);
            acc.points += 1;
        });
        acc
    }
}

/// ⌊n / d⌋ for d > 0.
#[inline]
fn floor_div(n: i64, d: i64) -> i64 {
    n.div_euclid(d)
}
