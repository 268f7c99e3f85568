//! Exact rasterisation of one triangle over the grid, and the error it accumulates.
//!
//! A grid point belongs to a triangle when every edge function is non-negative, with the
//! **ownership rule** for points exactly on an edge: of the two directions of an edge, the one
//! pointing down (dy < 0), or right when horizontal (dy = 0, dx > 0), owns its points; an edge on
//! the grid border owns its points in either direction (it has no second triangle). So every
//! point on a shared edge falls in exactly one triangle. The triangle's own vertices are skipped:
//! they are kept points and their error is zero by definition.

mod fresh_build;
pub(crate) mod peak;
#[cfg(target_arch = "x86_64")]
pub(crate) mod peak_avx2;
pub(crate) mod peak_finder;
pub(crate) mod span_sum;
#[cfg(target_arch = "x86_64")]
pub(crate) mod span_sum_avx2;
#[cfg(test)]
mod span_sum_tests;
pub(crate) mod triangle_memo;

use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::exact::predicates::{GridPoint, orient};
use crate::heightfield::Heightfield;
use span_sum::Kernel;

/// Error sums over the points one triangle owns.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct TriangleError {
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
pub(crate) struct Grid<'a> {
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
    pub(crate) fn on_border(&self, a: GridPoint, b: GridPoint) -> bool {
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
        // The vertices by row: bottom, middle, top (a stable sort, each swap flipping the
        // cyclic order). Rows below the middle one are bounded by the two edges at the bottom
        // vertex, rows from it up by the two at the top vertex (the third edge's constraint
        // holds strictly there, so it cannot bind). So each row advances two walks, with no
        // per-edge branching.
        let (mut bottom, mut mid, mut top) = (a, b, c);
        let mut flipped = false;
        if bottom[1] > mid[1] {
            (bottom, mid) = (mid, bottom);
            flipped = !flipped;
        }
        if mid[1] > top[1] {
            (mid, top) = (top, mid);
            flipped = !flipped;
        }
        if bottom[1] > mid[1] {
            (bottom, mid) = (mid, bottom);
            flipped = !flipped;
        }
        let (y0, y1, y2) = (bottom[1], mid[1], top[1]);
        // Counter-clockwise, bottom → top is the long edge's direction when bottom → middle →
        // top turns clockwise; then it runs up and bounds the triangle on the right, and the
        // two short edges on the left (and the other way round).
        let long_is_right = flipped;
        let (long, _) = self.edge(bottom, top, long_is_right);
        let (lower, lower_owned) = self.edge(bottom, mid, !long_is_right);
        let (upper, upper_owned) = self.edge(mid, top, !long_is_right);
        // A horizontal edge the triangle does not own: its row holds only that edge's points.
        let skip_row = if y0 == y1 && !lower_owned {
            y0
        } else if y1 == y2 && !upper_owned {
            y2
        } else {
            i64::MIN
        };
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
            xs: [bottom[0], mid[0], top[0]],
            middle,
            long,
            lower,
            upper,
            long_is_right,
            skip_row,
            za,
            gx: (dzb * cy - dzc * by) * inv_area,
            gy: (dzc * bx - dzb * cx) * inv_area,
            width: w,
        })
    }

    /// The walk along the edge from `lower` up to `upper` (rows `lower[1] ≤ upper[1]`) of a
    /// counter-clockwise triangle, which bounds it on the `right` or the left, and whether the
    /// triangle owns the edge's points. A horizontal edge bounds no row (a flat bottom or top:
    /// see `Spans::middle`) and gets an unused walk.
    ///
    /// Counter-clockwise, the edge runs p → q: up on the right, down on the left. Its function
    /// E(x, y) = −dy·x + offset(y) is the (unnormalised) barycentric weight of the opposite
    /// vertex; a point is owned iff E ≥ bias (bias 0 on an owned edge, 1 otherwise). With
    /// n(y) = offset(y) − bias and d = |dy|: a left edge (dy < 0) is x ≥ −⌊n/d⌋ and a right
    /// edge (dy > 0) x ≤ ⌊n/d⌋. Each walk starts at the edge's lower end.
    #[inline(always)]
    fn edge(&self, lower: GridPoint, upper: GridPoint, right: bool) -> (EdgeWalk, bool) {
        let rise = upper[1] - lower[1];
        // dx of p → q.
        let dx = if right {
            upper[0] - lower[0]
        } else {
            lower[0] - upper[0]
        };
        // The ownership rule: dy < 0 (a left edge that is not horizontal), or horizontal
        // with dx > 0, or on the border.
        let owned = (!right && rise > 0) || (rise == 0 && dx > 0) || self.on_border(lower, upper);
        if rise == 0 {
            return (EdgeWalk::default(), owned);
        }
        let signed_x = if right { lower[0] } else { -lower[0] };
        let walk = EdgeWalk::from_lower_end(signed_x, i64::from(!owned), dx, rise);
        (walk, owned)
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
    pub(crate) fn for_each_point(&self, tri: [GridPoint; 3], mut visit: impl FnMut(usize, f64)) {
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
    pub(crate) fn for_each_error(&self, tri: [GridPoint; 3], mut visit: impl FnMut(usize, f64)) {
        self.for_each_span(tri, |first, last, span| {
            let z = &self.z[first..=last];
            for (k, &zk) in z.iter().enumerate() {
                visit(first + k, (zk - span.at(k)).abs());
            }
        });
    }

    /// Whether a grid point the counter-clockwise triangle `tri` owns has an error |z − z̃|
    /// above `bound`, with the bits of [`for_each_error`](Self::for_each_error); rows after
    /// the first such point are skipped.
    pub(crate) fn any_error_above(&self, tri: [GridPoint; 3], bound: f64) -> bool {
        let mut above = false;
        self.for_each_span(tri, |first, last, span| {
            if !above {
                let z = &self.z[first..=last];
                above = z
                    .iter()
                    .enumerate()
                    .any(|(k, &zk)| (zk - span.at(k)).abs() > bound);
            }
        });
        above
    }

    /// The totals, in `units`, of the errors of the points each triangle `tris` yields owns
    /// (counter-clockwise, vertices excluded; each with a key), each given to `done` with its
    /// key: the errors of [`for_each_error`](Self::for_each_error), summed with the fastest
    /// kernel this CPU has (see [`span_sum`]; every kernel gives the same
    /// bits).
    pub(crate) fn sum_triangles<Key>(
        &self,
        units: ErrorUnits,
        tris: impl IntoIterator<Item = (Key, [GridPoint; 3])>,
        done: impl FnMut(Key, ErrorTotals),
    ) {
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = span_sum_avx2::Avx2::detect(units) {
            // SAFETY: `detect` found AVX2 on this CPU.
            unsafe { self.sum_triangles_avx2(k, tris, done) };
            return;
        }
        self.sum_triangles_with(span_sum::Scalar(units), tris, done);
    }

    /// The totals of all the triangles `tris` together (each counter-clockwise, proper): the
    /// sum of their [`sum_triangles`](Self::sum_triangles) totals, bit for bit (the sums are
    /// exact integers), in one set of running sums (no per-triangle reduction of the lanes).
    pub(crate) fn sum_all(
        &self,
        units: ErrorUnits,
        tris: impl IntoIterator<Item = [GridPoint; 3]>,
    ) -> ErrorTotals {
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = span_sum_avx2::Avx2::detect(units) {
            // SAFETY: `detect` found AVX2 on this CPU.
            return unsafe { self.sum_all_avx2(k, tris) };
        }
        self.sum_all_with(span_sum::Scalar(units), tris)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn sum_all_avx2(
        &self,
        k: span_sum_avx2::Avx2,
        tris: impl IntoIterator<Item = [GridPoint; 3]>,
    ) -> ErrorTotals {
        self.sum_all_with(k, tris)
    }

    #[inline(always)]
    fn sum_all_with<K: Kernel>(
        &self,
        k: K,
        tris: impl IntoIterator<Item = [GridPoint; 3]>,
    ) -> ErrorTotals {
        let mut sums = k.sums();
        for tri in tris {
            sums = self.add_triangle(&k, tri, sums);
        }
        k.totals(&sums)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn sum_triangles_avx2<Key>(
        &self,
        k: span_sum_avx2::Avx2,
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

    /// One triangle's totals with kernel `k`: the spans of
    /// [`for_each_span`](Self::for_each_span), but the rows through a vertex are worked out
    /// from the vertices. Why: a vertex is an extreme point of the triangle, so on its row it
    /// is an end of the span, and the points the triangle owns there start one column inside
    /// it, whichever edge owns what. So a pointed bottom or top row holds nothing (only its
    /// vertex), a flat one the columns strictly between its two vertices (or nothing, when
    /// the triangle does not own that edge), and the middle row runs from the long edge to the
    /// middle vertex's neighbour. At 2 % kept a triangle spans ≈ 7 rows: two of them skip the
    /// kernel, and no row tests the vertices.
    #[inline(always)]
    fn triangle_totals<K: Kernel>(&self, k: &K, tri: [GridPoint; 3]) -> ErrorTotals {
        k.totals(&self.add_triangle(k, tri, k.sums()))
    }

    /// `sums` with the points of triangle `tri` added (see
    /// [`triangle_totals`](Self::triangle_totals)).
    #[inline(always)]
    fn add_triangle<K: Kernel>(&self, k: &K, tri: [GridPoint; 3], sums: K::Sums) -> K::Sums {
        let Some(s) = self.spans(tri) else {
            return sums;
        };
        let mut sink = KernelRows {
            z: self.z,
            k,
            s: &s,
            sums,
            step: k.step(s.gx),
        };
        s.rows(&mut sink);
        sink.sums
    }

    /// The error sums of the points triangle `tri` owns.
    pub(crate) fn triangle_error(&self, tri: [GridPoint; 3]) -> TriangleError {
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

/// What takes the rows of [`Spans::rows`]. A trait rather than a closure: a closure's body
/// is not compiled with the AVX2 kernel's target feature, so the kernel's intrinsics in it
/// became calls.
trait RowSink {
    /// The columns `lo..=hi` of row `y` (empty when `hi < lo`).
    fn row(&mut self, y: i64, lo: i64, hi: i64);
}

/// Rows into a kernel's sums.
struct KernelRows<'a, K: Kernel> {
    z: &'a [f64],
    k: &'a K,
    s: &'a Spans,
    sums: K::Sums,
    step: K::Step,
}

impl<K: Kernel> RowSink for KernelRows<'_, K> {
    #[inline(always)]
    fn row(&mut self, y: i64, lo: i64, hi: i64) {
        let first = y as usize * self.s.width + lo as usize;
        let z = &self.z[first.min(self.z.len())..];
        let start = self.s.start(y, lo);
        self.k
            .add_span(&mut self.sums, &self.step, z, hi - lo + 1, start);
    }
}

/// z̃ along one row span: z̃(k) = start + k·step at the span's k-th column.
pub(crate) struct Interpolant {
    start: f64,
    step: f64,
}

impl Interpolant {
    /// z̃ at column `k` of the span.
    #[inline]
    pub(crate) fn at(&self, k: usize) -> f64 {
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
    /// The columns of the same vertices.
    xs: [i64; 3],
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

    /// Row by row, `sink.row(y, lo, hi)` for the columns `lo..=hi` the triangle owns on row `y`
    /// (vertices excluded; possibly empty, `hi < lo`): the spans of `columns`, but the rows
    /// through a vertex are worked out from the vertices. Why: a vertex is an extreme point of
    /// the triangle, so on its row it is an end of the span, and the points the triangle owns
    /// there start one column inside it, whichever edge owns what. So a pointed bottom or top
    /// row holds nothing (only its vertex), a flat one the columns strictly between its two
    /// vertices (or nothing, when the triangle does not own that edge), and the middle row runs
    /// from the long edge to the middle vertex's neighbour. At 2 % kept a triangle spans ≈ 7
    /// rows: two of them skip the kernel, and no row tests the vertices.
    #[inline(always)]
    fn rows(&self, sink: &mut impl RowSink) {
        let [y0, y1, y2] = self.ys;
        let [x0, x1, x2] = self.xs;
        let mut long = self.long;
        // The walks run from their lower ends; the first row of each section is the one above.
        // The walks go by value (picked by side once per section), which keeps them in
        // registers.
        if y0 < y1 {
            // Rows strictly between the bottom and the middle vertex: long and lower edge.
            long = self.rows_between(sink, long, self.lower, y0 + 1..y1);
        } else if self.skip_row != y0 {
            // A flat bottom the triangle owns.
            sink.row(y0, x0.min(x1) + 1, x0.max(x1) - 1);
        }
        if y1 < y2 {
            if y0 < y1 {
                // The middle row (its only vertex the middle one).
                let (lo, hi) = if self.long_is_right {
                    (x1 + 1, long.quotient)
                } else {
                    (-long.quotient, x1 - 1)
                };
                sink.row(y1, lo, hi);
            }
            // Rows strictly between the middle and the top vertex: long and upper edge.
            self.rows_between(sink, long, self.upper, y1 + 1..y2);
        } else if self.skip_row != y2 {
            // A flat top the triangle owns.
            sink.row(y2, x1.min(x2) + 1, x1.max(x2) - 1);
        }
    }

    /// The rows `rows` (holding no vertex) bounded by the walks `long` and `short`, which stand
    /// on the row below the first; returns the long edge's walk past the last row.
    #[inline(always)]
    fn rows_between(
        &self,
        sink: &mut impl RowSink,
        mut long: EdgeWalk,
        mut short: EdgeWalk,
        rows: std::ops::Range<i64>,
    ) -> EdgeWalk {
        long.advance();
        short.advance();
        let (mut left, mut right) = if self.long_is_right {
            (short, long)
        } else {
            (long, short)
        };
        for y in rows {
            sink.row(y, -left.quotient, right.quotient);
            left.advance();
            right.advance();
        }
        if self.long_is_right { right } else { left }
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

/// The grid of height field `hf`.
pub(crate) fn grid_of(hf: &Heightfield) -> Grid<'_> {
    Grid {
        width: hf.width() as i64,
        height: hf.height() as i64,
        z: hf.z(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::Evaluator;
    use crate::evaluator::test_grids::{fixture, random_subset};
    use rand::{RngExt, SeedableRng};
    use std::sync::Arc;

    /// `tri` counter-clockwise, or `None` when its corners are collinear.
    fn counter_clockwise(mut tri: [GridPoint; 3]) -> Option<[GridPoint; 3]> {
        let turn = orient(tri[0], tri[1], tri[2]);
        if turn < 0 {
            tri.swap(1, 2);
        }
        (turn != 0).then_some(tri)
    }

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
            let Some(tri) = counter_clockwise([0; 3].map(|_| [next(w), next(h)])) else {
                continue;
            };
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
                    / orient(tri[0], tri[1], tri[2]) as f64;
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

    /// The non-empty rows.
    struct Collect<'a>(&'a mut Vec<(i64, i64, i64)>);

    impl RowSink for Collect<'_> {
        fn row(&mut self, y: i64, lo: i64, hi: i64) {
            if lo <= hi {
                self.0.push((y, lo, hi));
            }
        }
    }

    #[test]
    fn vertex_rows_give_the_spans_of_the_walks() {
        // The rows `Spans::rows` works out from the vertices and the walks' rows must give the
        // very spans of `for_each_span` (tested against the ownership rule above), in the same
        // order: a vertex counted as owned would add an error of ≈ 0, which the totals alone
        // might not show.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x5a1e);
        let mut next = |bound: i64| rng.random_range(0..bound);
        for round in 0..6000 {
            let (w, h) = (2 + next(14), 2 + next(14));
            let z = vec![0.0; (w * h) as usize];
            let grid = Grid {
                width: w,
                height: h,
                z: &z,
            };
            let Some(tri) = counter_clockwise([0; 3].map(|_| [next(w), next(h)])) else {
                continue;
            };
            let mut expected = Vec::new();
            grid.for_each_span(tri, |first, last, _| {
                let (y, lo) = (first as i64 / w, first as i64 % w);
                expected.push((y, lo, lo + (last - first) as i64));
            });
            let mut got = Vec::new();
            if let Some(s) = grid.spans(tri) {
                s.rows(&mut Collect(&mut got));
            }
            assert_eq!(got, expected, "round {round}: {tri:?} on {w}x{h}");
        }
    }

    #[test]
    fn triangle_totals_are_the_sums_of_for_each_error() {
        // Random triangles on small grids (flat bottoms and tops owned or not, pointed ones,
        // middle vertices on either side, edges on the border, slivers) and large ones on a
        // bigger grid: the totals of every kernel must be the per-point errors' totals, bit for
        // bit, with the vertex rows worked out from the vertices.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x70ad);
        let mut next = |bound: i64| rng.random_range(0..bound);
        for round in 0..6000 {
            let (w, h) = if round % 10 == 0 {
                (40 + next(30), 40 + next(30))
            } else {
                (2 + next(12), 2 + next(12))
            };
            let z: Vec<f64> = (0..w * h)
                .map(|i| ((i * 37 % 11) as f64).sqrt() * 1.7 + (i % 5) as f64)
                .collect();
            let grid = Grid {
                width: w,
                height: h,
                z: &z,
            };
            let Some(tri) = counter_clockwise([0; 3].map(|_| [next(w), next(h)])) else {
                continue;
            };
            let units = ErrorUnits::new((w * h) as usize, 12.0);
            let mut expected = ErrorTotals::default();
            grid.for_each_error(tri, |_, d| expected.add_error(units, d));
            let mut by_scalar = ErrorTotals::default();
            grid.sum_triangles_with(span_sum::Scalar(units), [((), tri)], |_, t| by_scalar = t);
            let mut best = ErrorTotals::default();
            grid.sum_triangles(units, [((), tri)], |_, t| best = t);
            for got in [by_scalar, best] {
                assert_eq!(got.sum, expected.sum, "round {round}: {tri:?} on {w}x{h}");
                assert_eq!(got.sum_sq, expected.sum_sq, "round {round}: {tri:?}");
                assert_eq!(got.max.to_bits(), expected.max.to_bits(), "round {round}");
            }
        }
    }

    #[test]
    fn sums_of_many_triangles_are_the_sums_of_their_totals() {
        // Many triangles (overlapping: the sums need not tile anything) in one set of running
        // sums, with every kernel: the per-triangle totals added up, bit for bit, whatever the
        // lanes' wrapping biases add to over tens of thousands of points.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x5a11);
        let (w, h) = (61i64, 47i64);
        let z: Vec<f64> = (0..w * h).map(|_| rng.random::<f64>() * 300.0).collect();
        let grid = Grid {
            width: w,
            height: h,
            z: &z,
        };
        let units = ErrorUnits::new((w * h) as usize, 300.0);
        let mut tris = Vec::new();
        while tris.len() < 400 {
            let mut tri = [0; 3].map(|_| [rng.random_range(0..w), rng.random_range(0..h)]);
            match orient(tri[0], tri[1], tri[2]) {
                0 => continue,
                turn if turn < 0 => tri.swap(1, 2),
                _ => {}
            }
            tris.push(tri);
        }
        let mut expected = ErrorTotals::default();
        grid.sum_triangles(units, tris.iter().map(|&t| ((), t)), |_, t| {
            expected.add(&t)
        });
        let by_scalar = grid.sum_all_with(span_sum::Scalar(units), tris.iter().copied());
        let best = grid.sum_all(units, tris.iter().copied());
        for got in [by_scalar, best] {
            assert_eq!(got.sum, expected.sum);
            assert_eq!(got.sum_sq, expected.sum_sq);
            assert_eq!(got.max.to_bits(), expected.max.to_bits());
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
            let grid = Grid {
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
}
