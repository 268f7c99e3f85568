//! The triangles of a child mesh inside a region that its reused triangles leave uncovered.
//!
//! A composed child ([`compose`](super::compose)) reuses most of its parents' triangles; what
//! they leave uncovered, the region R, is tiled by the child's other triangles. Each of them has
//! an empty circle among all the child's points, so among R's points (the child's points in R
//! and on its boundary) too; and R's boundary edges are edges of the child, so Delaunay edges
//! of R's points. [`Region::wrap`] therefore finds them by *gift wrapping* from the boundary:
//! the triangle left of a Delaunay edge a → b has the apex c, among the points left of it, whose
//! circle through a, b and c holds no other (under the tie rule of
//! [`predicates`](super::predicates), a strict order of those points); each new triangle's other
//! two edges are wrapped in turn, until R is tiled. Points right of a → b need no test: the
//! triangle on that side has an empty circle, which holds the part of any circle through a, b
//! and a point on the left that lies right of a → b.
//!
//! Why not triangulate R's points and keep the triangles inside R: R's points lie along thin
//! seams between blocks, where insertion keeps flipping long thin triangles, and more than half
//! of that triangulation lies outside R. Wrapping makes only R's triangles, each after a search
//! of the grid near its edge (≈3× faster for a crossover's rows on jacksboro_65x65).

use super::predicates::{Circle, GridPoint, Lattice, in_circle, orient};
use super::triangulation::NONE;

/// Marks a [`Region::twins`] entry that is a boundary edge: the low bits are its index in the
/// boundary list given to [`Region::wrap`].
pub const BOUNDARY: u32 = 1 << 31;

/// Scratch and result of [`Region::wrap`], kept between calls.
#[derive(Clone, Debug, Default)]
pub struct Region {
    /// R's triangles, counter-clockwise, in the order found.
    pub triangles: Vec<[u32; 3]>,
    /// Per half-edge of `triangles` (3t + k runs from vertex k to vertex k + 1): the half-edge
    /// across it, [`BOUNDARY`] | i for the i-th boundary edge, or [`NONE`] on the grid border.
    pub twins: Vec<u32>,
    /// R's points, increasing, and their coordinates.
    points: Vec<u32>,
    at: Vec<GridPoint>,
    /// Per row y (and one past the last): the position in `points` of the first point of row y
    /// or later.
    row_start: Vec<u32>,
    edges: EdgeTable,
    /// Directed edges that still need a triangle on their left.
    queue: Vec<(u32, u32)>,
}

impl Region {
    /// Tiles R: `points` are R's points (the child's points inside R and on its boundary), on a
    /// grid `width × height`; R lies left of `v → u` for every boundary edge `(tag, u, v)` of
    /// `boundary` (an edge `u → v` of a reused triangle, with R across it; `tag` is the caller's).
    /// Fills [`triangles`](Self::triangles) and [`twins`](Self::twins). `None` when R is not
    /// what the caller says: a search finds no apex, a triangle overlaps another, or the tiling
    /// leaves a gap (guards; the caller then scores the child another way).
    pub fn wrap(
        &mut self,
        width: usize,
        height: usize,
        points: &[u32],
        boundary: &[(u32, u32, u32)],
    ) -> Option<()> {
        self.points.clear();
        self.points.extend_from_slice(points);
        self.points.sort_unstable();
        let lattice = Lattice::new(width);
        self.at.clear();
        self.at
            .extend(self.points.iter().map(|&p| lattice.point(p)));
        self.row_start.clear();
        let mut j = 0;
        for y in 0..=height as i64 {
            while j < self.at.len() && self.at[j][1] < y {
                j += 1;
            }
            self.row_start.push(j as u32);
        }
        self.triangles.clear();
        self.twins.clear();
        self.queue.clear();
        self.edges.reset(2 * boundary.len() + 3 * points.len());
        for (i, &(_, u, v)) in boundary.iter().enumerate() {
            // The reused triangle is left of u → v; R's triangle is to be found left of v → u.
            self.edges.insert(u, v, BOUNDARY | i as u32)?;
            self.queue.push((v, u));
        }
        while let Some((a, b)) = self.queue.pop() {
            if self.edges.get(a, b).is_some() {
                continue;
            }
            let c = self.apex(lattice, width, height, a, b)?;
            let t = self.triangles.len() as u32;
            self.triangles.push([a, b, c]);
            for (k, (x, y)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
                self.edges.insert(x, y, 3 * t + k as u32)?;
                // An edge on the grid border has nothing beyond it.
                if k > 0
                    && self.edges.get(y, x).is_none()
                    && !on_border(lattice, width, height, x, y)
                {
                    self.queue.push((y, x));
                }
            }
        }
        for t in 0..self.triangles.len() {
            let [a, b, c] = self.triangles[t];
            for (x, y) in [(a, b), (b, c), (c, a)] {
                let twin = match self.edges.get(y, x) {
                    Some(twin) => twin,
                    None if on_border(lattice, width, height, x, y) => NONE,
                    None => return None,
                };
                self.twins.push(twin);
            }
        }
        Some(())
    }

    /// The apex of the triangle left of `a → b` among R's points (see the module docs): first
    /// the best point in a small window around the edge (widened until it holds one), then every
    /// point in the box of that best point's circle, a box that shrinks to the circle of each
    /// better point found. Why that suffices: a point better than the apex lies inside its
    /// circle, and on the left of `a → b` a better point's circle lies inside a worse one's.
    fn apex(&self, lattice: Lattice, width: usize, height: usize, a: u32, b: u32) -> Option<u32> {
        let (pa, pb) = (lattice.point(a), lattice.point(b));
        let grid = [0, 0, width as i64, height as i64];
        // The first candidate: the point left of the edge nearest the centre of the square on
        // its left side (the edge turned a quarter left about its middle; the apex of a
        // well-shaped triangle lies near there), in a window widened until it holds one. The
        // tests are arithmetic, not branches: which points pass is data, and a branch per
        // point mispredicted about every other point.
        let (ex, ey) = (pb[0] - pa[0], pb[1] - pa[1]);
        // Twice the square's centre.
        let (mx, my) = (pa[0] + pb[0] - ey, pa[1] + pb[1] + ex);
        let mut half = ex.abs().max(ey.abs()) / 2 + 1;
        let mut first = None;
        while first.is_none() {
            let rect = clip(
                [
                    mx.div_euclid(2) - half,
                    my.div_euclid(2) - half,
                    mx.div_euclid(2) + half + 1,
                    my.div_euclid(2) + half + 1,
                ],
                grid,
            );
            let mut nearest = (i64::MAX, usize::MAX);
            for j in self.rows(rect[1], rect[3]) {
                let pd = self.at[j];
                let inside = (rect[0] <= pd[0]) & (pd[0] < rect[2]) & (orient(pa, pb, pd) > 0);
                let (dx, dy) = (2 * pd[0] - mx, 2 * pd[1] - my);
                let key = if inside { dx * dx + dy * dy } else { i64::MAX };
                if key < nearest.0 {
                    nearest = (key, j);
                }
            }
            if nearest.1 != usize::MAX {
                first = Some(nearest.1);
            } else if rect == grid {
                return None;
            } else {
                half *= 3;
            }
        }
        let j = first.expect("found above");
        let mut best = (self.points[j], self.at[j]);
        let mut circle = Circle::new(pa, pb, best.1);
        // Every point in the box of the best circle's left part; the box shrinks to a better
        // point's circle (the old box holds the new one's points of interest, so scanning it is
        // never wrong, only longer). A point can be better only inside the box, left of the
        // edge and on or in the circle: one rare branch.
        let mut cap = cap_box(pa, pb, best.1, width, height);
        for j in self.rows(cap[1], cap[3]) {
            let pd = self.at[j];
            let det = circle.det(pd);
            let candidate = (cap[0] <= pd[0])
                & (pd[0] < cap[2])
                & (pd[1] < cap[3])
                & (det >= 0)
                & (orient(pa, pb, pd) > 0);
            if candidate {
                let d = self.points[j];
                if d != best.0 && (det > 0 || in_circle([pa, pb, best.1, pd], [a, b, best.0, d])) {
                    best = (d, pd);
                    circle = Circle::new(pa, pb, pd);
                    let shrunk = cap_box(pa, pb, pd, width, height);
                    cap = [
                        cap[0].max(shrunk[0]),
                        cap[1],
                        cap[2].min(shrunk[2]),
                        cap[3].min(shrunk[3]),
                    ];
                }
            }
        }
        Some(best.0)
    }

    /// The positions in the point list of the points in rows `y0..y1` (clipped to the grid).
    fn rows(&self, y0: i64, y1: i64) -> std::ops::Range<usize> {
        let last = self.row_start.len() as i64 - 1;
        self.row_start[y0.clamp(0, last) as usize] as usize
            ..self.row_start[y1.clamp(0, last) as usize] as usize
    }
}

/// The grid box (half-open, clipped to the `width × height` grid) of the part of the circle
/// through `a`, `b` and `c` (counter-clockwise) that lies left of `a → b`: conservative, it holds
/// every grid point of that part, on the circle included. Why not the circle's own box: a point
/// near the edge makes a huge circle whose left part is a thin cap along the edge.
fn cap_box(a: GridPoint, b: GridPoint, c: GridPoint, width: usize, height: usize) -> [i64; 4] {
    let (ex, ey) = ((b[0] - a[0]) as f64, (b[1] - a[1]) as f64);
    let (bx, by) = (b[0] - a[0], b[1] - a[1]);
    let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
    let (lb, lc) = (bx * bx + by * by, cx * cx + cy * cy);
    // The circumcentre relative to a (exact integers below 2⁴⁴, one rounding in the division).
    let d = 2.0 * (bx * cy - by * cx) as f64;
    let ux = (cy * lb - by * lc) as f64 / d;
    let uy = (bx * lc - cx * lb) as f64 / d;
    let r = (ux * ux + uy * uy).sqrt();
    // The centre's distance left of the edge. A centre on the right makes a minor cap, which
    // lies between the edge and its copy moved left by the cap's height r + t; otherwise the
    // cap is most of the circle, and the circle's box is kept.
    let len = (ex * ex + ey * ey).sqrt();
    let (nx, ny) = (-ey / len, ex / len);
    let t = (ux - ex / 2.0) * nx + (uy - ey / 2.0) * ny;
    let margin = 1e-6 * (1.0 + r + len);
    let (ax, ay) = (a[0] as f64, a[1] as f64);
    let (ox, oy) = (ax + ux, ay + uy);
    let (xs, ys) = if t < 0.0 {
        let h = (r + t).max(0.0);
        (
            [ax, ax + ex, ax + h * nx, ax + ex + h * nx],
            [ay, ay + ey, ay + h * ny, ay + ey + h * ny],
        )
    } else {
        ([ox - r, ox + r, ox, ox], [oy - r, oy + r, oy, oy])
    };
    let lo = |v: [f64; 4], centre: f64| v.iter().copied().fold(f64::MAX, f64::min).max(centre - r);
    let hi = |v: [f64; 4], centre: f64| v.iter().copied().fold(f64::MIN, f64::max).min(centre + r);
    let clip = |v: f64, limit: usize| v.clamp(0.0, limit as f64) as i64;
    [
        clip((lo(xs, ox) - margin).floor(), width),
        clip((lo(ys, oy) - margin).floor(), height),
        clip((hi(xs, ox) + margin).ceil() + 1.0, width),
        clip((hi(ys, oy) + margin).ceil() + 1.0, height),
    ]
}

/// Does the edge between grid points `x` and `y` lie on the border of the `width × height` grid?
fn on_border(lattice: Lattice, width: usize, height: usize, x: u32, y: u32) -> bool {
    let (p, q) = (lattice.point(x), lattice.point(y));
    let (w, h) = (width as i64 - 1, height as i64 - 1);
    (p[0] == q[0] && (p[0] == 0 || p[0] == w)) || (p[1] == q[1] && (p[1] == 0 || p[1] == h))
}

/// `r` clipped to `grid` (half-open rectangles `[x0, y0, x1, y1]`).
fn clip(r: [i64; 4], grid: [i64; 4]) -> [i64; 4] {
    [
        r[0].max(grid[0]),
        r[1].max(grid[1]),
        r[2].min(grid[2]),
        r[3].min(grid[3]),
    ]
}

/// Calls `visit` with every grid point set in `bits` (bit `i` of word `i / 64`) inside the
/// half-open rectangle `[x0, y0, x1, y1]` of a grid `width` wide, row by row, until it returns
/// true; returns whether it did.
pub(super) fn for_each_in(
    bits: &[u64],
    width: usize,
    [x0, y0, x1, y1]: [i64; 4],
    mut visit: impl FnMut(u32) -> bool,
) -> bool {
    if x0 >= x1 {
        return false;
    }
    for y in y0..y1 {
        let (lo, hi) = (
            y as usize * width + x0 as usize,
            y as usize * width + x1 as usize,
        );
        let mut word = lo / 64;
        while word * 64 < hi {
            let mut set = bits[word];
            if word == lo / 64 {
                set &= u64::MAX << (lo % 64);
            }
            if (word + 1) * 64 > hi {
                set &= u64::MAX >> (64 - (hi - word * 64));
            }
            while set != 0 {
                let i = word * 64 + set.trailing_zeros() as usize;
                set &= set - 1;
                if visit(i as u32) {
                    return true;
                }
            }
            word += 1;
        }
    }
    false
}

/// A set of directed edges between grid points with a value each, by open addressing; emptied
/// in O(1) by a new stamp.
#[derive(Clone, Debug, Default)]
struct EdgeTable {
    /// (stamp, from, to, value) per slot.
    slots: Vec<(u32, u32, u32, u32)>,
    stamp: u32,
    len: usize,
}

impl EdgeTable {
    /// Empties the table, with room for about `expected` edges.
    fn reset(&mut self, expected: usize) {
        let want = (4 * expected.max(16)).next_power_of_two();
        self.stamp = self.stamp.wrapping_add(1);
        if self.slots.len() < want || self.stamp == 0 {
            self.slots.clear();
            self.slots.resize(want.max(self.slots.len()), (0, 0, 0, 0));
            self.stamp = 1;
        }
        self.len = 0;
    }

    fn slot_of(&self, from: u32, to: u32) -> usize {
        let key = (u64::from(from) << 32) | u64::from(to);
        (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 32) as usize & (self.slots.len() - 1)
    }

    fn get(&self, from: u32, to: u32) -> Option<u32> {
        let mask = self.slots.len() - 1;
        let mut s = self.slot_of(from, to);
        loop {
            let (stamp, f, t, value) = self.slots[s];
            if stamp != self.stamp {
                return None;
            }
            if (f, t) == (from, to) {
                return Some(value);
            }
            s = (s + 1) & mask;
        }
    }

    /// Inserts `from → to`; `None` if it is there already (two triangles left of one edge) or
    /// the table is full.
    fn insert(&mut self, from: u32, to: u32, value: u32) -> Option<()> {
        if 2 * (self.len + 1) > self.slots.len() {
            self.grow();
        }
        let mask = self.slots.len() - 1;
        let mut s = self.slot_of(from, to);
        loop {
            let (stamp, f, t, _) = self.slots[s];
            if stamp != self.stamp {
                self.slots[s] = (self.stamp, from, to, value);
                self.len += 1;
                return Some(());
            }
            if (f, t) == (from, to) {
                return None;
            }
            s = (s + 1) & mask;
        }
    }

    /// Doubles the table, keeping its edges.
    fn grow(&mut self) {
        let old: Vec<_> = self
            .slots
            .iter()
            .copied()
            .filter(|s| s.0 == self.stamp)
            .collect();
        let size = 2 * self.slots.len();
        self.slots.clear();
        self.slots.resize(size, (0, 0, 0, 0));
        self.stamp = 1;
        self.len = 0;
        for (_, f, t, v) in old {
            self.insert(f, t, v);
        }
    }
}
