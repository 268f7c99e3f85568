//! The triangles of a child mesh inside a region that its reused triangles leave uncovered.
//!
//! A composed child ([`compose`](crate::evaluator::compose)) reuses most of its parents' triangles; what
//! they leave uncovered, the region R, is tiled by the child's other triangles. Each of them has
//! an empty circle among all the child's points, so among R's points (the child's points in R
//! and on its boundary) too; and R's boundary edges are edges of the child, so Delaunay edges
//! of R's points. [`Region::wrap`] therefore finds them by *gift wrapping* from the boundary:
//! the triangle left of a Delaunay edge a → b has the apex c, among the points left of it, whose
//! circle through a, b and c holds no other (under the tie rule of
//! [`predicates`](crate::evaluator::exact::predicates), a strict order of those points); each new triangle's other
//! two edges are wrapped in turn, until R is tiled. Points right of a → b need no test: the
//! triangle on that side has an empty circle, which holds the part of any circle through a, b
//! and a point on the left that lies right of a → b.
//!
//! # The apex search
//! The circles through a and b form a pencil: with e = b − a and e⊥ = e turned a quarter left,
//! the circle through a, b and a point p left of the edge has its centre at a + e/2 + σ(p)·e⊥,
//! σ(p) = s(p)/2 with s(p) = (p − a)·(p − b) / (e × (p − a)), and on the left of the edge a
//! circle with a smaller σ lies inside one with a larger (p is inside the circle through c iff
//! s(p) < s(c)). The apex is so the point of least s, ties (co-circular points, common on grids)
//! decided by [`in_circle`]'s tie rule. Numerator and denominator are integers below 2³⁰, exact
//! in f64, and one correctly rounded division is monotone: the apex has the least *rounded*
//! s, and a point whose rounded s is strictly larger cannot be it. So a scan keeps the least
//! rounded s, with no test per point but compares and selects, four points per AVX2 instruction
//! where the CPU has it; only when two points share the least value (a tie, or two fractions
//! within one rounding) do the exact predicates decide among them.
//!
//! The scan reads R's points as contiguous runs: sorted by row and again by column, each order
//! with the position of every row's (column's) first point, so the points of a band of rows
//! (columns) are one run, and any superset of the candidates that holds only R's points is as
//! good as the candidates. A first scan takes the band (of rows or of columns, whichever holds
//! fewer points) through a window near the edge; the least s found bounds the apex to the part
//! of that circle left of the edge, and a second scan takes the rest of that part's band.
//!
//! Why not triangulate R's points and keep the triangles inside R: R's points lie along thin
//! seams between blocks, where insertion keeps flipping long thin triangles, and more than half
//! of that triangulation lies outside R. Wrapping makes only R's triangles, each after a search
//! of the grid near its edge.

mod edge_table;
mod scan;
#[cfg(target_arch = "x86_64")]
mod scan_avx2;

use crate::evaluator::exact::predicates::{GridPoint, Lattice, in_circle};
use crate::evaluator::mesh::canonical_triangulation::NONE;
use edge_table::{EdgeTable, Queued, VACANT};
use scan::{Band, Edge, GUESS, Least, Scalar, Scan, guess_lines};

/// Marks a [`Region::twins`] entry that is a boundary edge: the low bits are its index in the
/// boundary list given to [`Region::wrap`].
pub(crate) const BOUNDARY: u32 = 1 << 31;

/// Scratch and result of [`Region::wrap`], kept between calls.
///
/// Inside, R's points go by a *local* index: R's points first, increasing (so by row, then
/// column), then any boundary end missing from them (never an apex).
#[derive(Clone, Debug, Default)]
pub(crate) struct Region {
    /// R's triangles, counter-clockwise, in the order found.
    pub triangles: Vec<[u32; 3]>,
    /// Per half-edge of `triangles` (3t + k runs from vertex k to vertex k + 1): the half-edge
    /// across it, [`BOUNDARY`] | i for the i-th boundary edge, or [`NONE`] on the grid border.
    pub twins: Vec<u32>,
    /// Grid index per local index.
    points: Vec<u32>,
    /// Coordinates per local index.
    at: Vec<GridPoint>,
    /// Local index per grid index, where `points` confirms it (stale entries are never cleared).
    local: Vec<u32>,
    /// The local ends (u, v) of each boundary edge.
    ends: Vec<(u32, u32)>,
    /// R's points by row, and by column.
    rows: Band,
    columns: Band,
    /// Scratch of the sorts: a bitset of part of the grid (left empty), and each column's
    /// next position.
    bits: Vec<u64>,
    cursor: Vec<u32>,
    edges: EdgeTable,
}

impl Region {
    /// Tiles R: `points` are R's points (the child's points inside R and on its boundary), on a
    /// grid `width × height`; R lies left of `v → u` for every boundary edge `(tag, u, v)` of
    /// `boundary` (an edge `u → v` of a reused triangle, with R across it; `tag` is the caller's).
    /// Fills [`triangles`](Self::triangles) and [`twins`](Self::twins). `None` when R is not
    /// what the caller says: a search finds no apex, a triangle overlaps another, or the tiling
    /// leaves a gap (guards; the caller then scores the child another way).
    pub(crate) fn wrap(
        &mut self,
        width: usize,
        height: usize,
        points: &[u32],
        boundary: &[(u32, u32, u32)],
    ) -> Option<()> {
        self.wrap_with(width, height, points, boundary, true)
    }

    /// [`wrap`](Self::wrap), with the AVX2 scan where the CPU has it and `simd` allows it.
    fn wrap_with(
        &mut self,
        width: usize,
        height: usize,
        points: &[u32],
        boundary: &[(u32, u32, u32)],
        simd: bool,
    ) -> Option<()> {
        self.prepare(width, height, points, boundary);
        #[cfg(target_arch = "x86_64")]
        if simd && scan_avx2::available() {
            // SAFETY: the CPU has AVX2 and FMA.
            return unsafe { self.tile_avx2(width, height) };
        }
        let _ = simd;
        self.tile::<Scalar>(width, height)
    }

    /// Local indices, coordinates, and both bands of R's points.
    fn prepare(
        &mut self,
        width: usize,
        height: usize,
        points: &[u32],
        boundary: &[(u32, u32, u32)],
    ) {
        let lattice = Lattice::new(width);
        let cells = width * height;
        // R's points increasing, once each. Indices past the grid are no grid points: never an
        // apex (boundary ends among them get local indices below).
        self.sort(cells, points);
        let n = self.points.len();
        // Coordinates, local indices, and the points per row and per column (counted one line
        // on, then summed into each line's start).
        self.at.clear();
        self.at
            .extend(self.points.iter().map(|&p| lattice.point(p)));
        if self.local.len() < cells {
            self.local.resize(cells, 0);
        }
        let local = &mut self.local[..cells];
        for (j, &p) in self.points.iter().enumerate() {
            local[p as usize] = j as u32;
        }
        let (rows, columns) = (&mut self.rows, &mut self.columns);
        rows.start.clear();
        rows.start.resize(height + 1, 0);
        columns.start.clear();
        columns.start.resize(width + 1, 0);
        {
            let (row_count, column_count) = (&mut rows.start[1..], &mut columns.start[1..]);
            for &[x, y] in &self.at {
                row_count[y as usize] += 1;
                column_count[x as usize] += 1;
            }
        }
        for start in [&mut rows.start, &mut columns.start] {
            let mut sum = 0;
            for line in start.iter_mut() {
                sum += *line;
                *line = sum;
            }
        }
        // The bands: by row, the local order itself; by column, a counting sort of it.
        rows.id.clear();
        rows.id.extend(0..n as u32);
        rows.fill(&self.at);
        columns.id.clear();
        columns.id.resize(n, 0);
        self.cursor.clear();
        self.cursor.extend_from_slice(&columns.start[..width]);
        {
            let (cursor, id) = (&mut self.cursor[..width], &mut columns.id[..n]);
            for (j, &[x, _]) in self.at.iter().enumerate() {
                let at = &mut cursor[x as usize];
                id[*at as usize] = j as u32;
                *at += 1;
            }
        }
        columns.fill(&self.at);
        // Boundary ends missing from R's points (never, from the callers) get local indices
        // too.
        self.ends.clear();
        self.ends.reserve(boundary.len());
        for &(_, u, v) in boundary {
            let u = self.local_of(u, &lattice);
            let v = self.local_of(v, &lattice);
            self.ends.push((u, v));
        }
    }

    /// Fills `points` with the grid points among `points` (below `cells`), increasing, once
    /// each: through a bitset of the grid when their span is short next to their number (one
    /// pass over the points and one over the span's words, no comparisons), else by sorting.
    fn sort(&mut self, cells: usize, points: &[u32]) {
        self.points.clear();
        let (mut lo, mut hi) = (u32::MAX, 0);
        for &p in points {
            if (p as usize) < cells {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        if lo > hi {
            return;
        }
        let (first, last) = (lo as usize / 64, hi as usize / 64);
        if last - first > 4 * points.len() + 64 {
            self.points
                .extend(points.iter().filter(|&&p| (p as usize) < cells));
            self.points.sort_unstable();
            self.points.dedup();
            return;
        }
        if self.bits.len() <= last - first {
            self.bits.resize(last - first + 1, 0);
        }
        for &p in points {
            if (p as usize) < cells {
                self.bits[p as usize / 64 - first] |= 1 << (p % 64);
            }
        }
        // Read in order and left empty for the next call.
        for (k, word) in self.bits[..=last - first].iter_mut().enumerate() {
            let mut set = std::mem::take(word);
            while set != 0 {
                self.points
                    .push(((first + k) * 64) as u32 + set.trailing_zeros());
                set &= set - 1;
            }
        }
    }

    /// The local index of grid index `p`, given one if it has none yet.
    #[inline(always)]
    fn local_of(&mut self, p: u32, lattice: &Lattice) -> u32 {
        match self.local.get(p as usize) {
            Some(&j) if self.points.get(j as usize) == Some(&p) => j,
            _ => self.add_end(p, lattice),
        }
    }

    /// The local index of boundary end `p`, not one of R's points: past them (never an apex),
    /// given when first met.
    #[cold]
    fn add_end(&mut self, p: u32, lattice: &Lattice) -> u32 {
        let n = self.rows.start.last().map_or(0, |&n| n as usize);
        if let Some(k) = self.points[n..].iter().position(|&q| q == p) {
            return (n + k) as u32;
        }
        let j = self.points.len() as u32;
        if let Some(local) = self.local.get_mut(p as usize) {
            *local = j;
        }
        self.points.push(p);
        self.at.push(lattice.point(p));
        j
    }

    /// [`tile`](Self::tile) with the AVX2 scan.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn tile_avx2(&mut self, width: usize, height: usize) -> Option<()> {
        self.tile::<scan_avx2::Avx2>(width, height)
    }

    /// The wrapping itself, on prepared points (see [`wrap`](Self::wrap)).
    #[inline(always)]
    fn tile<S: Scan>(&mut self, width: usize, height: usize) -> Option<()> {
        let Self {
            triangles,
            twins,
            points,
            at,
            rows,
            columns,
            ends,
            edges,
            ..
        } = self;
        let candidates = Candidates {
            points,
            at,
            rows,
            columns,
        };
        wrap_front::<S>(&candidates, ends, edges, triangles, twins, width, height)
    }
}

/// R's prepared points, as the searches read them (plain slices: a function taking them
/// knows nothing else writes them, so it keeps them in registers).
#[derive(Clone, Copy, Debug)]
struct Candidates<'a> {
    points: &'a [u32],
    at: &'a [GridPoint],
    rows: &'a Band,
    columns: &'a Band,
}

/// The wrapping from the boundary `ends` (local indices) inward (see [`Region::wrap`]).
#[inline(always)]
fn wrap_front<S: Scan>(
    found: &Candidates,
    ends: &[(u32, u32)],
    edges: &mut EdgeTable,
    triangles: &mut Vec<[u32; 3]>,
    twins: &mut Vec<u32>,
    width: usize,
    height: usize,
) -> Option<()> {
    triangles.clear();
    twins.clear();
    edges.reset(ends.len() + 3 * found.points.len());
    for (i, &(u, v)) in ends.iter().enumerate() {
        // The reused triangle is left of u → v; R's triangle is to be found left of v → u.
        let (slot, d) = edges.entry(u, v);
        edges.claim(slot, d, BOUNDARY | i as u32)?;
        edges.queue.push((v, u, Queued::across(slot, d)));
    }
    while let Some((a, b, queued)) = edges.queue.pop() {
        let (slot, d) = queued.slot();
        if edges.value(slot, d) != VACANT {
            continue;
        }
        let c = found.apex::<S>(a, b)?;
        let t = triangles.len() as u32;
        triangles.push([a, b, c].map(|j| found.points[j as usize]));
        // a → b: vacant (above), and the edge that queued it is across.
        let back = edges.claim(slot, d, 3 * t)?;
        twins.extend([back, NONE, NONE]);
        if back & BOUNDARY == 0 {
            twins[back as usize] = 3 * t;
        }
        for (k, (x, y)) in [(b, c), (c, a)].into_iter().enumerate() {
            let e = 3 * t + 1 + k as u32;
            let (slot, d) = edges.entry(x, y);
            let back = edges.claim(slot, d, e)?;
            if back != VACANT {
                // Twins are linked as the second of the two is claimed.
                twins[e as usize] = back;
                if back & BOUNDARY == 0 {
                    twins[back as usize] = e;
                }
            } else if !on_border(found.at[x as usize], found.at[y as usize], width, height) {
                // An edge on the grid border has nothing beyond it.
                edges.queue.push((y, x, Queued::across(slot, d)));
            }
        }
    }
    // An edge with nothing across lies on the grid border, or R is not tiled.
    let lattice = Lattice::new(width);
    for (tri, twins) in triangles.iter().zip(twins.chunks_exact(3)) {
        for k in 0..3 {
            if twins[k] == NONE {
                let (p, q) = (tri[k], tri[(k + 1) % 3]);
                if !on_border(lattice.point(p), lattice.point(q), width, height) {
                    return None;
                }
            }
        }
    }
    Some(())
}

impl Candidates<'_> {
    /// The apex of the triangle left of `a → b` (local indices) among R's points, as a local
    /// index; `None` when no point lies left of the edge. See the module docs: a scan of the
    /// band through a window on the edge's left, then of the band of the best circle's left
    /// part beyond it. Why that suffices: a point better than the apex lies inside its circle,
    /// and on the left of `a → b` a better point's circle lies inside a worse one's.
    #[inline(always)]
    fn apex<S: Scan>(&self, a: u32, b: u32) -> Option<u32> {
        let (pa, pb) = (self.at[a as usize], self.at[b as usize]);
        let edge = Edge::new(pa, pb);
        // The window: the lines of the left part of the circle whose s is GUESS (the apex of a
        // well-shaped triangle lies inside it), as rows or as columns, whichever holds fewer
        // points.
        let [[x0, x1], [y0, y1]] = guess_lines(pa, pb);
        let rows = self.rows.span(y0, y1);
        let columns = self.columns.span(x0, x1);
        let (band, axis, window) = if rows[1] - rows[0] <= columns[1] - columns[0] {
            (&self.rows, 1, rows)
        } else {
            (&self.columns, 0, columns)
        };
        let mut scan = S::new(&edge);
        let window = Band::blocks(window);
        scan.scan(band, window.clone());
        let least = scan.least();
        // A point inside the guess circle has its circle's left part inside the window (and
        // GUESS is exact, so the rounded comparison is the exact one); otherwise the rest of
        // the best circle's lines, before the window and after it.
        if least > GUESS {
            let cap = if least < f64::INFINITY {
                let [lo, hi] = edge.cap_lines(least, axis);
                Band::blocks(band.span(lo, hi))
            } else {
                band.all()
            };
            scan.scan(band, cap.start..cap.end.min(window.start));
            scan.scan(band, cap.start.max(window.end)..cap.end);
        }
        match scan.outcome() {
            Least::Nothing => None,
            Least::One(at) => Some(band.id[at]),
            Least::Shared(least) => Some(self.settle(&scan, band, &edge, axis, least, a, b)),
        }
    }

    /// The apex among the points whose rounded s is `least` (the least, shared): the exact
    /// predicates with the tie rule decide, one point against the best so far. They all lie on
    /// the lines of that circle's left part.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn settle<S: Scan>(
        &self,
        scan: &S,
        band: &Band,
        edge: &Edge,
        axis: usize,
        least: f64,
        a: u32,
        b: u32,
    ) -> u32 {
        let (pa, pb) = (self.at[a as usize], self.at[b as usize]);
        let (ga, gb) = (self.points[a as usize], self.points[b as usize]);
        let [lo, hi] = edge.cap_lines(least, axis);
        let mut best: Option<u32> = None;
        scan.each_equal(band, Band::blocks(band.span(lo, hi)), least, |pos| {
            let d = band.id[pos];
            best = Some(match best {
                Some(c)
                    if !in_circle(
                        [pa, pb, self.at[c as usize], self.at[d as usize]],
                        [ga, gb, self.points[c as usize], self.points[d as usize]],
                    ) =>
                {
                    c
                }
                _ => d,
            });
        });
        best.expect("the least value is a point's")
    }
}

/// Does the edge between grid points `p` and `q` lie on the border of the `width × height`
/// grid?
#[inline(always)]
fn on_border(p: GridPoint, q: GridPoint, width: usize, height: usize) -> bool {
    let (w, h) = (width as i64 - 1, height as i64 - 1);
    // `&` and `|`, not `&&` and `||`: one branch on the answer, not one per test.
    (p[0] == q[0]) & ((p[0] == 0) | (p[0] == w)) | (p[1] == q[1]) & ((p[1] == 0) | (p[1] == h))
}

/// Calls `visit` with every grid point set in `bits` (bit `i` of word `i / 64`) inside the
/// half-open rectangle `[x0, y0, x1, y1]` of a grid `width` wide, row by row, until it returns
/// true; returns whether it did.
pub(crate) fn for_each_in(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::mesh::canonical_form::canonical_set;
    use crate::evaluator::mesh::canonical_triangulation::{Triangulation, next};
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    /// Wraps the triangles of a Delaunay triangulation that `inside` picks, from the edges of
    /// the others around them, with the scan `simd` selects.
    fn wrap_part(
        tri: &Triangulation,
        (w, h): (usize, usize),
        inside: &[bool],
        simd: bool,
    ) -> Option<Vec<[u32; 3]>> {
        let (mut points, mut boundary) = (Vec::new(), Vec::new());
        for t in 0..tri.len() {
            for k in 0..3 {
                let e = 3 * t + k;
                let twin = tri.twin[e];
                if inside[t] {
                    points.push(tri.vertices[e]);
                } else if twin != NONE && inside[twin as usize / 3] {
                    let next = tri.vertices[next(e as u32) as usize];
                    boundary.push((e as u32, tri.vertices[e], next));
                }
            }
        }
        let mut region = Region::default();
        region.wrap_with(w, h, &points, &boundary, simd)?;
        Some(region.triangles)
    }

    /// Every triangle of R is Delaunay among all the points, so among R's: wrapping must find
    /// exactly them, co-circular grid points included (dense random subsets of small grids
    /// have many), with either scan.
    #[test]
    fn wrapping_finds_the_delaunay_triangles_of_the_region() {
        let mut rng = Pcg64Mcg::seed_from_u64(7);
        let mut tiled = 0;
        for round in 0..1000 {
            let (w, h) = (rng.random_range(3..40), rng.random_range(3..40));
            let density = [0.05, 0.3, 0.8][round % 3];
            let corners = [0, w - 1, (h - 1) * w, h * w - 1];
            let kept: Vec<u32> = (0..w * h)
                .filter(|i| corners.contains(i) || rng.random_bool(density))
                .map(|i| i as u32)
                .collect();
            let mut tri = Triangulation::default();
            tri.rebuild_delaunay(w, &kept);
            // A box of the grid: the triangles with a vertex in it.
            let (x0, y0) = (rng.random_range(0..w), rng.random_range(0..h));
            let (x1, y1) = (rng.random_range(x0..w) + 1, rng.random_range(y0..h) + 1);
            let inside: Vec<bool> = (0..tri.len())
                .map(|t| {
                    tri.triangle(t).iter().any(|&p| {
                        let (x, y) = (p as usize % w, p as usize / w);
                        (x0..x1).contains(&x) && (y0..y1).contains(&y)
                    })
                })
                .collect();
            if inside.iter().all(|&i| i) {
                // No boundary to wrap from (the callers never ask for this).
                continue;
            }
            tiled += 1;
            let expected: Vec<[u32; 3]> = (0..tri.len())
                .filter(|&t| inside[t])
                .map(|t| tri.triangle(t))
                .collect();
            for simd in [true, false] {
                let found = wrap_part(&tri, (w, h), &inside, simd)
                    .unwrap_or_else(|| panic!("round {round}, simd {simd}: no tiling"));
                assert_eq!(
                    canonical_set(&found),
                    canonical_set(&expected),
                    "round {round} ({w}×{h}), simd {simd}"
                );
            }
        }
        assert!(tiled > 700, "only {tiled} rounds had a boundary");
    }

    /// A region that is not what the caller says (a boundary edge whose far side holds no
    /// point) is refused, not tiled wrongly.
    #[test]
    fn wrapping_refuses_a_region_with_no_apex() {
        // A 3×3 grid: the edge 0 → 2 along the bottom border, R claimed above... of nothing
        // but the edge's own ends.
        let mut region = Region::default();
        assert_eq!(region.wrap(3, 3, &[0, 2], &[(0, 2, 0)]), None);
    }
}
