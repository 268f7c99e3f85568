//! Exact rasterisation of one triangle over the grid, and the error it accumulates.
//!
//! A grid point belongs to a triangle when every edge function is non-negative, with the
//! **ownership rule** for points exactly on an edge: of the two directions of an edge, the one
//! pointing down (dy < 0), or right when horizontal (dy = 0, dx > 0), owns its points; an edge on
//! the grid border owns its points in either direction (it has no second triangle). So every
//! point on a shared edge falls in exactly one triangle. The triangle's own vertices are skipped:
//! they are kept points and their error is zero by definition.

use super::errors::{ErrorTotals, ErrorUnits};
use super::predicates::{GridPoint, orient};
use super::span_sum::{self, Kernel};

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

    /// The set-up of a triangle's row spans (see [`Spans`]), or `None` for a triangle of area ½,
    /// which owns no grid point.
    #[inline(always)]
    fn spans(&self, tri: [GridPoint; 3]) -> Option<Spans> {
        let [a, b, c] = tri;
        let area = orient(a, b, c);
        debug_assert!(area > 0, "triangle must be counter-clockwise and proper");
        if area == 1 {
            // Pick's theorem: a lattice triangle of area ½ holds no grid point but its vertices.
            // A fifth of the triangles of a 30 %-dense mesh are such; skipping their set-up
            // saves about a tenth of a dense mesh's raster time.
            return None;
        }
        let w = self.width as usize;
        let za = self.z[(a[1] as usize) * w + a[0] as usize];
        let zb = self.z[(b[1] as usize) * w + b[0] as usize];
        let zc = self.z[(c[1] as usize) * w + c[0] as usize];
        // Edge k runs p → q, opposite vertex k; its function E(x, y) = −dy·x + offset(y) is the
        // (unnormalised) barycentric weight of vertex k. The point is owned iff E ≥ bias (bias 0
        // on an owned edge, 1 otherwise). With n(y) = offset(y) − bias and d = |dy|:
        // dy < 0 ⇔ x ≥ −⌊n/d⌋ (a left edge) and dy > 0 ⇔ x ≤ ⌊n/d⌋ (a right edge).
        let edges = [(b, c), (c, a), (a, b)];
        let dx = edges.map(|(p, q)| q[0] - p[0]);
        let dy = edges.map(|(p, q)| q[1] - p[1]);
        let bias = [0, 1, 2].map(|k| {
            let (p, q) = edges[k];
            i64::from(!(dy[k] < 0 || (dy[k] == 0 && dx[k] > 0) || self.on_border(p, q)))
        });
        // Each walk starts at its edge's lower end (p when the edge runs up, q when down). A
        // horizontal edge bounds no row (a flat bottom or top: see `middle` below) and gets an
        // unused walk.
        let walk_up = |k: usize| {
            let (p, q) = edges[k];
            if dy[k] == 0 {
                return EdgeWalk::default();
            }
            let signed_x = if dy[k] > 0 { p[0] } else { -q[0] };
            EdgeWalk::from_lower_end(signed_x, bias[k], dx[k], dy[k].abs())
        };
        // The vertices by row: bottom, middle, top. Rows below the middle one are bounded by the
        // two edges at the bottom vertex, rows from it up by the two at the top vertex (the third
        // edge's constraint holds strictly there, so it cannot bind). So each row advances two
        // walks, with no per-edge branching.
        let ys = [a[1], b[1], c[1]];
        let (mut v0, mut v1, mut v2) = (0, 1, 2);
        if ys[v0] > ys[v1] {
            std::mem::swap(&mut v0, &mut v1);
        }
        if ys[v1] > ys[v2] {
            std::mem::swap(&mut v1, &mut v2);
        }
        if ys[v0] > ys[v1] {
            std::mem::swap(&mut v0, &mut v1);
        }
        let (y0, y1, y2) = (ys[v0], ys[v1], ys[v2]);
        // Edge k is opposite vertex k: the long edge joins bottom and top, the lower edge bottom
        // and middle, the upper edge middle and top. The long edge is a right edge iff it runs up.
        let (long, lower, upper) = (v1, v2, v0);
        // A horizontal edge the triangle does not own: its row holds only that edge's points.
        let skip_row = [lower, upper]
            .into_iter()
            .find(|&k| dy[k] == 0 && bias[k] == 1)
            .map_or(i64::MIN, |k| edges[k].0[1]);
        // The plane through the vertices as z̃ = z_a + gx·(x − x_a) + gy·(y − y_a), from height
        // differences (a flat triangle has exactly zero gradient, so no rounding noise).
        let (dzb, dzc) = (zb - za, zc - za);
        let (bx, by) = ((b[0] - a[0]) as f64, (b[1] - a[1]) as f64);
        let (cx, cy) = ((c[0] - a[0]) as f64, (c[1] - a[1]) as f64);
        let inv_area = 1.0 / area as f64;
        // Below the middle row the lower edge; from it up, the upper edge. (On the middle row the
        // lower edge would give the same span: both short edges end at the middle vertex, and
        // whichever excludes it, the vertex rule does too.) A flat top keeps the lower edge to
        // the end; a flat bottom starts on the upper edge.
        let middle = if y1 < y2 { y1 } else { y2 + 1 };
        Some(Spans {
            tri,
            ys: [y0, y1, y2],
            middle,
            long: walk_up(long),
            lower: walk_up(lower),
            upper: walk_up(upper),
            long_is_right: dy[long] > 0,
            skip_row,
            za,
            gx: (dzb * cy - dzc * by) * inv_area,
            gy: (dzc * bx - dzb * cx) * inv_area,
            width: w,
        })
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
        let Some(mut s) = self.spans(tri) else {
            return;
        };
        let [y0, _, y2] = s.ys;
        let mut short = s.lower;
        // An exclusive range: an inclusive one carries an extra flag through the loop.
        for y in y0..y2 + 1 {
            if y == s.middle {
                short = s.upper;
            }
            if let Some((first, len, span)) = s.span(y, &short) {
                visit(first, first + len - 1, &span);
            }
            s.long.advance();
            short.advance();
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
    /// [`for_each_error`](Self::for_each_error), and `slot` into `owner` at the same points.
    /// Span-wise slices instead of a call per point let the loop run without bounds checks (the
    /// fresh build writes every grid point this way); both stores in one loop, because the
    /// spans of a sparse mesh are short (≈2.6 grid points per row at 2 % kept) and a second pass per span
    /// costs its own set-up (5 % fewer instructions per evaluation at 2 % kept).
    #[inline]
    pub fn write_errors(
        &self,
        tri: [GridPoint; 3],
        errors: &mut [f64],
        owner: &mut [u32],
        slot: u32,
    ) {
        self.for_each_span(tri, |first, last, span| {
            let z = &self.z[first..=last];
            let out = &mut errors[first..=last][..z.len()];
            let own = &mut owner[first..=last][..z.len()];
            // An i32 counter (see `Interpolant::at_i32`), which also lets the loop vectorise.
            for k in 0..z.len() as i32 {
                let i = k as usize;
                out[i] = (z[i] - span.at_i32(k)).abs();
                own[i] = slot;
            }
        });
    }

    /// The totals, in `units`, of the errors of the points the counter-clockwise triangle `tri`
    /// owns (vertices excluded): the same errors as [`write_errors`](Self::write_errors) writes,
    /// without writing them, for a score that keeps no per-point error.
    pub fn error_totals(&self, tri: [GridPoint; 3], units: ErrorUnits) -> ErrorTotals {
        let mut out = ErrorTotals::default();
        self.sum_triangles(units, std::iter::once(((), tri)), |_, t| out = t);
        out
    }

    /// [`error_totals`](Self::error_totals) of every triangle `tris` yields (counter-clockwise,
    /// each with a key), each given to `done` with its key: with the fastest kernel this CPU has
    /// (see [`span_sum`](super::span_sum); every kernel gives the same bits).
    pub fn sum_triangles<Key>(
        &self,
        units: ErrorUnits,
        tris: impl IntoIterator<Item = (Key, [GridPoint; 3])>,
        done: impl FnMut(Key, ErrorTotals),
    ) {
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = span_sum::Avx2::detect(units) {
            // SAFETY: `detect` found AVX2 on this CPU.
            unsafe { self.sum_triangles_avx2(k, tris, done) };
            return;
        }
        self.sum_triangles_with(span_sum::Scalar(units), tris, done);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn sum_triangles_avx2<Key>(
        &self,
        k: span_sum::Avx2,
        tris: impl IntoIterator<Item = (Key, [GridPoint; 3])>,
        done: impl FnMut(Key, ErrorTotals),
    ) {
        self.sum_triangles_with(k, tris, done);
    }

    #[inline(always)]
    fn sum_triangles_with<K: Kernel, Key>(
        &self,
        k: K,
        tris: impl IntoIterator<Item = (Key, [GridPoint; 3])>,
        mut done: impl FnMut(Key, ErrorTotals),
    ) {
        for (key, tri) in tris {
            done(key, self.triangle_totals(&k, tri));
        }
    }

    /// One triangle's totals with kernel `k`.
    #[inline(always)]
    fn triangle_totals<K: Kernel>(&self, k: &K, tri: [GridPoint; 3]) -> ErrorTotals {
        let Some(mut s) = self.spans(tri) else {
            return ErrorTotals::default();
        };
        let mut sums = k.sums();
        let step = k.step(s.gx);
        let [y0, _, y2] = s.ys;
        // Rows below the middle one on the lower edge, the rest on the upper edge. Only the
        // first row, the middle one and the last can hold a vertex, so those are taken apart
        // from the rest: a test on every row mispredicted on the first and last.
        let mut short = s.lower;
        let lower_end = s.middle.min(y2 + 1);
        if y0 < lower_end {
            self.total_row::<K, true>(k, &mut s, &mut short, &mut sums, &step, y0);
            let last = if lower_end == y2 + 1 { y2 } else { lower_end };
            for y in y0 + 1..last {
                self.total_row::<K, false>(k, &mut s, &mut short, &mut sums, &step, y);
            }
            if last < lower_end {
                self.total_row::<K, true>(k, &mut s, &mut short, &mut sums, &step, last);
            }
        }
        let mut short = s.upper;
        let middle = s.middle;
        if middle <= y2 {
            self.total_row::<K, true>(k, &mut s, &mut short, &mut sums, &step, middle);
            for y in middle + 1..y2 {
                self.total_row::<K, false>(k, &mut s, &mut short, &mut sums, &step, y);
            }
            if middle < y2 {
                self.total_row::<K, true>(k, &mut s, &mut short, &mut sums, &step, y2);
            }
        }
        k.totals(&sums)
    }

    /// Row `y` of `s` into `sums` (`VERTICES`: the row may hold a vertex), then the walks
    /// advance.
    #[inline(always)]
    fn total_row<K: Kernel, const VERTICES: bool>(
        &self,
        k: &K,
        s: &mut Spans,
        short: &mut EdgeWalk,
        sums: &mut K::Sums,
        step: &K::Step,
        y: i64,
    ) {
        let (mut lo, mut hi) = if s.long_is_right {
            (-short.quotient, s.long.quotient)
        } else {
            (-s.long.quotient, short.quotient)
        };
        if VERTICES {
            (lo, hi) = s.without_vertices(y, lo, hi);
        }
        if y == s.skip_row {
            hi = lo - 1;
        }
        let first = y as usize * s.width + lo as usize;
        let z = &self.z[first.min(self.z.len())..];
        k.add_span(sums, step, z, hi - lo + 1, s.start(y, lo));
        s.long.advance();
        short.advance();
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

/// z̃ along one row span: z̃(k) = start + k·step at the span's k-th column.
pub struct Interpolant {
    start: f64,
    step: f64,
}

impl Interpolant {
    /// z̃ at column `k` of the span.
    #[inline]
    pub fn at(&self, k: usize) -> f64 {
        // Exact: a span is shorter than the grid's side, < 2¹⁴.
        self.at_i32(k as i32)
    }

    /// [`at`](Self::at) for an `i32` column, the same bits; an `i32` converts to f64 in one
    /// instruction, a `usize` in a branchy sequence on x86-64.
    #[inline]
    fn at_i32(&self, k: i32) -> f64 {
        self.start + k as f64 * self.step
    }
}

/// The row spans of one triangle: its rows, the walks along its edges, its plane.
#[derive(Clone, Copy)]
struct Spans {
    tri: [GridPoint; 3],
    /// The rows of the bottom, middle and top vertex.
    ys: [i64; 3],
    /// The first row bounded by the upper edge rather than the lower (past the top for a flat
    /// top).
    middle: i64,
    long: EdgeWalk,
    lower: EdgeWalk,
    upper: EdgeWalk,
    long_is_right: bool,
    /// The row of a horizontal edge the triangle does not own, or `i64::MIN`.
    skip_row: i64,
    za: f64,
    gx: f64,
    gy: f64,
    width: usize,
}

impl Spans {
    /// Row `y`'s span as (first column, last column), vertices excluded; empty when last < first.
    #[inline(always)]
    fn columns(&self, y: i64, short: &EdgeWalk) -> (i64, i64) {
        let (mut lo, mut hi) = if self.long_is_right {
            (-short.quotient, self.long.quotient)
        } else {
            (-self.long.quotient, short.quotient)
        };
        let [y0, y1, y2] = self.ys;
        if y == y0 || y == y1 || y == y2 {
            (lo, hi) = self.without_vertices(y, lo, hi);
        }
        if y == self.skip_row {
            hi = lo - 1;
        }
        (lo, hi)
    }

    /// The span `lo..=hi` of row `y` without the triangle's vertices on it. Vertices are kept
    /// points and contribute nothing; a vertex is an extreme point of the triangle, so on its
    /// row it can only be an end of the span.
    #[inline(always)]
    fn without_vertices(&self, y: i64, mut lo: i64, mut hi: i64) -> (i64, i64) {
        for v in self.tri {
            if v[1] == y {
                if v[0] == lo {
                    lo += 1;
                } else if v[0] == hi {
                    hi -= 1;
                }
            }
        }
        (lo, hi)
    }

    /// z̃ at the first column `lo` of row `y`'s span.
    #[inline(always)]
    fn start(&self, y: i64, lo: i64) -> f64 {
        let a = self.tri[0];
        self.za + self.gy * (y - a[1]) as f64 + self.gx * (lo - a[0]) as f64
    }

    /// Row `y`'s span as (first grid index, length, interpolant), if not empty.
    #[inline(always)]
    fn span(&self, y: i64, short: &EdgeWalk) -> Option<(usize, usize, Interpolant)> {
        let (lo, hi) = self.columns(y, short);
        (lo <= hi).then(|| {
            (
                y as usize * self.width + lo as usize,
                (hi - lo + 1) as usize,
                Interpolant {
                    start: self.start(y, lo),
                    step: self.gx,
                },
            )
        })
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
    /// Starts on the row of the edge's lower end, where n = s·d·x − bias (x that end's column,
    /// s = ±1 the edge's side, bias 0 or 1): there ⌊n/d⌋ = s·x − bias with remainder
    /// bias·(d − 1), no division needed. The per-row step needs one only when |step| ≥ d.
    /// Why it matters: the set-up of small triangles dominates a dense mesh's raster time.
    #[inline]
    fn from_lower_end(signed_x: i64, bias: i64, step: i64, divisor: i64) -> Self {
        let (step_quotient, step_remainder) = if (0..divisor).contains(&step) {
            (0, step)
        } else if (-divisor..0).contains(&step) {
            (-1, step + divisor)
        } else {
            // Under the grid limits |step| < 2¹⁴, so the division runs in 32 bits (several
            // times faster than 64-bit division on common CPUs).
            let (step32, d32) = (step as i32, divisor as i32);
            (step32.div_euclid(d32) as i64, step32.rem_euclid(d32) as i64)
        };
        Self {
            quotient: signed_x - bias,
            remainder: bias * (divisor - 1),
            step_quotient,
            step_remainder,
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
    use rand::{RngExt, SeedableRng};

    /// Ownership decided point by point, straight from the rule in the module docs.
    fn owns_by_rule(grid: &Grid<'_>, tri: [GridPoint; 3], at: GridPoint) -> bool {
        if tri.contains(&at) {
            return false;
        }
        (0..3).all(|k| {
            let (p, q) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let owned = dy < 0 || (dy == 0 && dx > 0) || grid.on_border(p, q);
            orient(p, q, at) >= i64::from(!owned)
        })
    }

    #[test]
    fn spans_hold_exactly_the_points_the_rule_gives_a_triangle() {
        // Random triangles on small grids hit every shape the span walk special-cases: flat
        // bottoms and tops, a middle vertex left or right of the long edge, edges one row tall,
        // slivers, and edges on the border. Each must visit exactly the points the ownership rule
        // gives it, once each, with z̃ the plane through its vertices.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x9e37_79b9);
        let mut next = |bound: i64| rng.random_range(0..bound);
        for round in 0..4000 {
            let (w, h) = (2 + next(12), 2 + next(12));
            let z: Vec<f64> = (0..w * h).map(|i| ((i * 37 % 11) as f64).sqrt()).collect();
            let grid = Grid {
                width: w,
                height: h,
                z: &z,
            };
            let mut tri = [0; 3].map(|_| [next(w), next(h)]);
            let turn = orient(tri[0], tri[1], tri[2]);
            if turn == 0 {
                continue;
            }
            if turn < 0 {
                tri.swap(1, 2);
            }
            let mut seen = vec![0u32; (w * h) as usize];
            grid.for_each_point(tri, |i, zt| {
                seen[i] += 1;
                // z̃ from barycentric weights, independently of the span arithmetic.
                let at = [i as i64 % w, i as i64 / w];
                let weight = |p: GridPoint, q: GridPoint| orient(p, q, at) as f64;
                let zv = tri.map(|v| z[(v[1] * w + v[0]) as usize]);
                let expected = (weight(tri[1], tri[2]) * zv[0]
                    + weight(tri[2], tri[0]) * zv[1]
                    + weight(tri[0], tri[1]) * zv[2])
                    / turn.abs() as f64;
                assert!(
                    (zt - expected).abs() < 1e-12,
                    "round {round} {tri:?} at {at:?}"
                );
            });
            for (i, &count) in seen.iter().enumerate() {
                let at = [i as i64 % w, i as i64 / w];
                let owned = owns_by_rule(&grid, tri, at);
                assert_eq!(
                    count,
                    u32::from(owned),
                    "round {round}: {tri:?} on {w}x{h}, {at:?}"
                );
            }
        }
    }

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
            let mut owner = vec![0u32; w * h];
            grid.write_errors(tri, &mut written, &mut owner, 9);
            assert_eq!(
                written.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
                expected.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
                "{tri:?}"
            );
            // The owner is marked at exactly the points written.
            let owned: Vec<bool> = expected.iter().map(|&d| d >= 0.0).collect();
            assert!(owned.contains(&true), "{tri:?} owns no point");
            assert_eq!(
                owner.iter().map(|&o| o == 9).collect::<Vec<_>>(),
                owned,
                "{tri:?}"
            );
        }
    }
}
