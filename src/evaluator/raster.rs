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
    /// Does the segment a–b lie on the grid's border? Such an edge belongs to one triangle only.
    #[inline]
    pub fn on_border(&self, a: GridPoint, b: GridPoint) -> bool {
        (a[0] == b[0] && (a[0] == 0 || a[0] == self.width - 1))
            || (a[1] == b[1] && (a[1] == 0 || a[1] == self.height - 1))
    }

    /// Visits every grid point the counter-clockwise triangle `tri` owns (vertices excluded) one
    /// row span at a time: `visit(first_index, last_index, interpolant)`. Spans are never empty
    /// and never contain a vertex.
    #[inline]
    fn for_each_span(
        &self,
        tri: [GridPoint; 3],
        mut visit: impl FnMut(usize, usize, &Interpolant),
    ) {
        let [a, b, c] = tri;
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        debug_assert!(area > 0, "triangle must be counter-clockwise and proper");
        let w = self.width as usize;
        let za = self.z[(a[1] as usize) * w + a[0] as usize];
        let zb = self.z[(b[1] as usize) * w + b[0] as usize];
        let zc = self.z[(c[1] as usize) * w + c[0] as usize];
        let y_lo = a[1].min(b[1]).min(c[1]);
        let y_hi = a[1].max(b[1]).max(c[1]);
        // Edge k runs p → q; its function E(x, y) = slope·x + offset(y) is the (unnormalised)
        // barycentric weight of the vertex opposite it. The point is owned iff E ≥ bias
        // (bias 0 on an owned edge, 1 otherwise). With n(y) = offset(y) − bias and d = |slope|:
        // slope > 0 ⇔ x ≥ −⌊n/d⌋ and slope < 0 ⇔ x ≤ ⌊n/d⌋. ⌊n/d⌋ is walked down the rows
        // exactly as a quotient and remainder (n grows by dx per row): no division per row.
        let edges = [(b, c, za), (c, a, zb), (a, b, zc)];
        let mut slope = [0i64; 3];
        let mut offset = [0i64; 3]; // offset(y), starting at y = y_lo
        let mut walk = [EdgeWalk::default(); 3];
        let mut skip_row = None; // the row of a horizontal edge this triangle does not own
        for (k, &(p, q, _)) in edges.iter().enumerate() {
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            slope[k] = -dy;
            offset[k] = dx * (y_lo - p[1]) + dy * p[0];
            let owned = dy < 0 || (dy == 0 && dx > 0) || self.on_border(p, q);
            let bias = i64::from(!owned);
            if dy == 0 {
                // A horizontal edge constrains only its own row (the triangle lies on one side).
                if !owned {
                    skip_row = Some(p[1]);
                }
            } else {
                walk[k] = EdgeWalk::new(offset[k] - bias, dx, dy.abs());
            }
        }
        let s1: f64 = (0..3).map(|k| slope[k] as f64 * edges[k].2).sum();
        let inv_area = 1.0 / area as f64;
        for y in y_lo..=y_hi {
            let (mut lo, mut hi) = (i64::MIN, i64::MAX);
            for k in 0..3 {
                if slope[k] > 0 {
                    lo = lo.max(-walk[k].quotient);
                } else if slope[k] < 0 {
                    hi = hi.min(walk[k].quotient);
                }
            }
            if y == a[1] || y == b[1] || y == c[1] {
                // Vertices are kept points and contribute nothing. A vertex is an extreme point
                // of the triangle, so on its row it can only be an end of the span.
                for v in tri {
                    if v[1] == y {
                        if v[0] == lo {
                            lo += 1;
                        } else if v[0] == hi {
                            hi -= 1;
                        }
                    }
                }
            }
            if lo <= hi && skip_row != Some(y) {
                let s0: f64 = (0..3)
                    .map(|k| (slope[k] * lo + offset[k]) as f64 * edges[k].2)
                    .sum();
                let row = (y as usize) * w;
                visit(
                    row + lo as usize,
                    row + hi as usize,
                    &Interpolant { s0, s1, inv_area },
                );
            }
            for k in 0..3 {
                offset[k] += edges[k].1[0] - edges[k].0[0];
                walk[k].advance();
            }
        }
    }

    /// Visits every grid point the counter-clockwise triangle `tri` owns (vertices excluded) with
    /// its index and its interpolated height z̃.
    #[inline]
    pub fn for_each_point(&self, tri: [GridPoint; 3], mut visit: impl FnMut(usize, f64)) {
        self.for_each_span(tri, |first, last, span| {
            for (k, i) in (first..=last).enumerate() {
                visit(i, span.at(k));
            }
        });
    }

    /// Visits every grid point the counter-clockwise triangle `tri` owns (vertices excluded) with
    /// its index and its error |z − z̃|, the same bits [`triangle_error`](Self::triangle_error)
    /// adds up.
    #[inline]
    pub fn for_each_error(&self, tri: [GridPoint; 3], mut visit: impl FnMut(usize, f64)) {
        self.for_each_span(tri, |first, last, span| {
            let z = &self.z[first..=last];
            for (k, &zk) in z.iter().enumerate() {
                visit(first + k, (zk - span.at(k)).abs());
            }
        });
    }

    /// Writes the error |z − z̃| of every grid point the counter-clockwise triangle `tri` owns
    /// (vertices excluded) into `errors` (row-major, one per grid point), the same bits as
    /// [`for_each_error`](Self::for_each_error), and calls `visit(first, last)` once per row
    /// span written. Span-wise slices instead of a call per point let the loop run without
    /// bounds checks (the fresh build writes every grid point this way).
    #[inline]
    pub fn write_errors(
        &self,
        tri: [GridPoint; 3],
        errors: &mut [f64],
        mut visit: impl FnMut(usize, usize),
    ) {
        self.for_each_span(tri, |first, last, span| {
            let z = &self.z[first..=last];
            let out = &mut errors[first..=last];
            for (k, (e, &zk)) in out.iter_mut().zip(z).enumerate() {
                *e = (zk - span.at(k)).abs();
            }
            visit(first, last);
        });
    }

    /// The error sums of the points triangle `tri` owns.
    pub fn triangle_error(&self, tri: [GridPoint; 3]) -> TriangleError {
        let mut acc = TriangleError::default();
        self.for_each_span(tri, |first, last, span| {
            let z = &self.z[first..=last];
            for (k, &zk) in z.iter().enumerate() {
                let d = (zk - span.at(k)).abs();
                acc.sum += d;
                acc.sum_sq += d * d;
                if d > acc.max {
                    acc.max = d;
                }
            }
            acc.points += z.len() as u32;
        });
        acc
    }
}

/// z̃ along one row span: z̃(k) = (s0 + k·s1) / area at the span's k-th column.
pub struct Interpolant {
    s0: f64,
    s1: f64,
    inv_area: f64,
}

impl Interpolant {
    /// z̃ at column `k` of the span.
    #[inline]
    pub fn at(&self, k: usize) -> f64 {
        (self.s0 + k as f64 * self.s1) * self.inv_area
    }
}

/// ⌊n / d⌋ along the rows of an edge, where n grows by `step` per row: kept as a quotient and
/// a remainder in `0..d`, so each row costs two additions and a comparison.
#[derive(Clone, Copy, Debug, Default)]
struct EdgeWalk {
    quotient: i64,
    remainder: i64,
    step_quotient: i64,
    step_remainder: i64,
    divisor: i64,
}

impl EdgeWalk {
    /// Starts at n/d. Under the grid limits |n| < 2²⁹ and d ≤ 2¹⁴, so the divisions run in
    /// 32 bits (several times faster than 64-bit division on common CPUs).
    fn new(n: i64, step: i64, divisor: i64) -> Self {
        let (n32, step32, d32) = (n as i32, step as i32, divisor as i32);
        debug_assert!(n32 as i64 == n && step32 as i64 == step && d32 as i64 == divisor);
        if divisor == 1 {
            // An edge one row tall, common in dense meshes: ⌊n/1⌋ = n, no division needed.
            return Self {
                quotient: n,
                remainder: 0,
                step_quotient: step,
                step_remainder: 0,
                divisor,
            };
        }
        Self {
            quotient: n32.div_euclid(d32) as i64,
            remainder: n32.rem_euclid(d32) as i64,
            step_quotient: step32.div_euclid(d32) as i64,
            step_remainder: step32.rem_euclid(d32) as i64,
            divisor,
        }
    }

    #[inline]
    fn advance(&mut self) {
        self.quotient += self.step_quotient;
        self.remainder += self.step_remainder;
        if self.remainder >= self.divisor {
            self.remainder -= self.divisor;
            self.quotient += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_errors_gives_the_bits_of_for_each_error() {
        // A 7×5 grid of uneven heights (so no error is zero by accident) and triangles with
        // horizontal, vertical, steep and shallow edges, some on the border: every span shape.
        let (w, h) = (7usize, 5usize);
        let z: Vec<f64> = (0..w * h)
            .map(|i| ((i * 37 % 11) as f64).sqrt() * 1.3)
            .collect();
        let grid = Grid {
            width: w as i64,
            height: h as i64,
            z: &z,
        };
        let triangles: [[GridPoint; 3]; 4] = [
            [[0, 0], [6, 0], [0, 4]],
            [[6, 0], [6, 4], [0, 4]],
            [[1, 0], [5, 3], [0, 2]],
            [[2, 1], [6, 2], [3, 4]],
        ];
        for tri in triangles {
            let mut expected = vec![-1.0; w * h];
            grid.for_each_error(tri, |i, d| expected[i] = d);
            let mut written = vec![-1.0; w * h];
            let mut spans = Vec::new();
            grid.write_errors(tri, &mut written, |first, last| spans.push((first, last)));
            assert_eq!(
                written.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
                expected.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
                "{tri:?}"
            );
            let in_spans = spans.iter().map(|(a, b)| b - a + 1).sum::<usize>();
            let owned = expected.iter().filter(|&&d| d >= 0.0).count();
            assert!(owned > 0, "{tri:?} owns no point");
            assert_eq!(in_spans, owned, "{tri:?}");
        }
    }
}
