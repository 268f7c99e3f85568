//! The apex search's scan over a band of R's points, one point at a time (the portable
//! twin of [`scan_avx2`](super::scan_avx2)).

use crate::evaluator::exact::predicates::GridPoint;
use std::ops::Range;

/// R's points in one order (by row, or by column) as coordinate arrays that a scan reads four
/// at a time, and where each line (row or column) starts.
#[derive(Clone, Debug, Default)]
pub(super) struct Band {
    /// Coordinates per position, padded to whole blocks of four with NaN (never left of an edge,
    /// so never a candidate).
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<f64>,
    /// Local index per position (padding: 0, never read).
    pub(super) id: Vec<u32>,
    /// Per line and one past the last: the position of the first point on that line or later.
    pub(super) start: Vec<u32>,
}

impl Band {
    /// The positions `[from, to)` of the points on lines `lo..hi` (clipped to the grid).
    #[inline(always)]
    pub(super) fn span(&self, lo: i64, hi: i64) -> [usize; 2] {
        let last = self.start.len() - 1;
        let at = |line: i64| self.start[(line.max(0) as usize).min(last)] as usize;
        [at(lo), at(hi)]
    }

    /// The blocks of four positions that cover `[from, to)`; empty when it is.
    #[inline(always)]
    pub(super) fn blocks([from, to]: [usize; 2]) -> Range<usize> {
        if from < to {
            from / 4..to.div_ceil(4)
        } else {
            0..0
        }
    }

    /// Every block.
    pub(super) fn all(&self) -> Range<usize> {
        0..self.x.len() / 4
    }

    /// Fills the coordinates from `id` (local indices into `at`) and pads the arrays.
    pub(super) fn fill(&mut self, at: &[GridPoint]) {
        let padded = self.id.len().next_multiple_of(4);
        self.x.clear();
        self.y.clear();
        self.x.resize(padded, f64::NAN);
        self.y.resize(padded, f64::NAN);
        for ((x, y), &j) in self.x.iter_mut().zip(self.y.iter_mut()).zip(&self.id) {
            let [px, py] = at[j as usize];
            (*x, *y) = (px as f64, py as f64);
        }
        self.id.resize(padded, 0);
    }
}

/// An edge a → b of the search, as the scans want it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Edge {
    pub(super) ax: f64,
    pub(super) ay: f64,
    pub(super) bx: f64,
    pub(super) by: f64,
    pub(super) ex: f64,
    pub(super) ey: f64,
    /// |e|².
    len2: f64,
}

/// The s of the first window's circle (see [`Region::apex`] and [`guess_lines`]).
pub(super) const GUESS: f64 = 1.0;

/// The columns and rows (half-open) that hold the part left of `a → b` of the circle through
/// a and b whose s is [`GUESS`] (σ = 1/2: the centre a + (e + e⊥)/2, the radius |e|/√2), in
/// integers: conservative, as [`Edge::cap_lines`], but cheaper (this is every search's).
#[inline(always)]
pub(super) fn guess_lines(a: GridPoint, b: GridPoint) -> [[i64; 2]; 2] {
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    // r ≤ (M + m/2)/√2 ≤ (182/256)·(M + m/2) with M, m the larger and smaller of |ex|, |ey|
    // ((M + m/2)² ≥ M² + m² as M ≥ m), rounded up.
    let (ax, ay) = (ex.abs(), ey.abs());
    let (big, small) = if ax < ay { (ay, ax) } else { (ax, ay) };
    let r = (((2 * big + small) * 91) >> 8) + 1;
    // Twice the centre, and the circle's extreme lines.
    let (cx, cy) = (2 * a[0] + ex - ey, 2 * a[1] + ey + ex);
    let (x0, x1, y0, y1) = (
        (cx >> 1) - r,
        (cx >> 1) + r + 1,
        (cy >> 1) - r,
        (cy >> 1) + r + 1,
    );
    // The circle's extreme point along ±x (±y) lies left of the edge unless the edge is
    // steeper than 45° that way (e × (centre ± r·axis − a) = |e|²/2 ± r·(−ey or ex)); then
    // the part ends at an end of the edge. Selects, not branches.
    let (steep_x, steep_y) = (ey * ey > ex * ex, ex * ex > ey * ey);
    let (lo_x, hi_x) = (a[0].min(b[0]), a[0].max(b[0]) + 1);
    let (lo_y, hi_y) = (a[1].min(b[1]), a[1].max(b[1]) + 1);
    [
        [
            if steep_x & (ey < 0) { lo_x } else { x0 },
            if steep_x & (ey > 0) { hi_x } else { x1 },
        ],
        [
            if steep_y & (ex > 0) { lo_y } else { y0 },
            if steep_y & (ex < 0) { hi_y } else { y1 },
        ],
    ]
}

impl Edge {
    pub(super) fn new(a: GridPoint, b: GridPoint) -> Self {
        Self {
            ax: a[0] as f64,
            ay: a[1] as f64,
            bx: b[0] as f64,
            by: b[1] as f64,
            ex: (b[0] - a[0]) as f64,
            ey: (b[1] - a[1]) as f64,
            len2: ((b[0] - a[0]).pow(2) + (b[1] - a[1]).pow(2)) as f64,
        }
    }

    /// The lines (columns if `axis` is 0, rows if 1) that hold the part left of the edge of
    /// the circle through a and b whose s is `s` (finite; see the module docs): conservative,
    /// every grid point of that part, on the circle included, lies on one of them. Why not the
    /// circle's extent: a point near the edge makes a huge circle whose left part is a thin
    /// cap along the edge.
    #[inline(always)]
    pub(super) fn cap_lines(&self, s: f64, axis: usize) -> [i64; 2] {
        // The centre is a + e/2 + σ·e⊥, the radius |e|·√(1/4 + σ²).
        let sigma = 0.5 * s;
        let r = (self.len2 * (0.25 + sigma * sigma)).sqrt();
        // Along the axis: a's and b's coordinates, e's and e⊥'s (also e × the axis).
        let (ak, bk, ek, nk) = if axis == 0 {
            (self.ax, self.bx, self.ex, -self.ey)
        } else {
            (self.ay, self.by, self.ey, self.ex)
        };
        let c = ak + 0.5 * ek + sigma * nk;
        // The part is convex: its extreme along the axis is the circle's where that point
        // lies left of the edge (e × (centre ± r·axis − a) = σ|e|² ± r·nk ≥ 0), else an end of
        // the edge. The circle's is kept unless the point is clearly right (a rounding near
        // the line would only make the lines wider).
        let (base, reach) = (sigma * self.len2, r * nk);
        let tolerance = 1e-9 * (base.abs() + reach.abs());
        let margin = 1e-6 * (1.0 + r);
        // Selects, not branches: which side wins is data.
        let (low_end, high_end) = if ak < bk { (ak, bk) } else { (bk, ak) };
        let hi = if base + reach < -tolerance {
            high_end
        } else {
            c + r + margin
        };
        let lo = if base - reach < -tolerance {
            low_end
        } else {
            c - r - margin
        };
        // Outwards to whole lines: `as` truncates, which is the floor from 0 up, and lines
        // below 0 are clipped anyway (it saturates far out).
        [lo as i64, (hi + 1.0) as i64]
    }

    /// s of the point (x, y) (see the module docs), rounded once; +∞ unless the point lies
    /// strictly left of the edge (NaN coordinates included). The numerator and denominator are
    /// exact (integers below 2³⁰), whatever the order of the operations or fused ones.
    #[inline(always)]
    pub(super) fn key(&self, x: f64, y: f64) -> f64 {
        let (qx, qy) = (x - self.ax, y - self.ay);
        let den = self.ex * qy - self.ey * qx;
        let num = qx * (x - self.bx) + qy * (y - self.by);
        if den > 0.0 { num / den } else { f64::INFINITY }
    }
}

/// What a search's scans found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Least {
    /// No point left of the edge.
    Nothing,
    /// The one point (its position in the band) with the least rounded s: the apex.
    One(usize),
    /// The least rounded s, shared by more than one point.
    Shared(f64),
}

/// A scan over blocks of a [`Band`] that keeps the least rounded s (see the module docs), per
/// lane: its value, the position of its first point, and whether a later point has it too.
pub(super) trait Scan {
    /// An empty scan for the edge.
    fn new(edge: &Edge) -> Self;
    /// Scans positions `4·blocks.start..4·blocks.end` (within the band's padded arrays; none
    /// when `blocks` is empty or runs backwards).
    fn scan(&mut self, band: &Band, blocks: Range<usize>);
    /// The least value seen (+∞ when none).
    fn least(&self) -> f64;
    /// The outcome so far.
    fn outcome(&self) -> Least;
    /// Calls `visit` with every position of `blocks` whose rounded s is `least`, in order.
    fn each_equal(&self, band: &Band, blocks: Range<usize>, least: f64, visit: impl FnMut(usize));
}

/// One point at a time (every target, and the reference of the tests).
#[derive(Clone, Copy, Debug)]
pub(super) struct Scalar {
    pub(super) edge: Edge,
    pub(super) least: f64,
    pub(super) at: usize,
    pub(super) shared: bool,
}

impl Scan for Scalar {
    #[inline(always)]
    fn new(edge: &Edge) -> Self {
        Self {
            edge: *edge,
            least: f64::INFINITY,
            at: 0,
            shared: false,
        }
    }

    #[inline(always)]
    fn scan(&mut self, band: &Band, blocks: Range<usize>) {
        // A range may run backwards (a cap that ends before the window): empty, as the loop's.
        let range = 4 * blocks.start..4 * blocks.end.max(blocks.start);
        let (xs, ys) = (&band.x[range.clone()], &band.y[range.clone()]);
        for (k, (&x, &y)) in xs.iter().zip(ys).enumerate() {
            let s = self.edge.key(x, y);
            let (less, equal) = (s < self.least, s == self.least);
            self.shared = (self.shared | equal) & !less;
            if less {
                self.least = s;
                self.at = range.start + k;
            }
        }
    }

    #[inline(always)]
    fn least(&self) -> f64 {
        self.least
    }

    #[inline(always)]
    fn outcome(&self) -> Least {
        if self.least == f64::INFINITY {
            Least::Nothing
        } else if self.shared {
            Least::Shared(self.least)
        } else {
            Least::One(self.at)
        }
    }

    #[inline(always)]
    fn each_equal(
        &self,
        band: &Band,
        blocks: Range<usize>,
        least: f64,
        mut visit: impl FnMut(usize),
    ) {
        for pos in 4 * blocks.start..4 * blocks.end {
            if self.edge.key(band.x[pos], band.y[pos]) == least {
                visit(pos);
            }
        }
    }
}
