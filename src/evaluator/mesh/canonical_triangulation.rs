//! The canonical Delaunay triangulation of a set of grid points, as half-edge arrays.
//!
//! The points are inserted one by one into their bounding box's two triangles, each followed by
//! Lawson flips under the project's tie rule ([`predicates::in_circle`], exact integers), which
//! makes the result a function of the point set alone (see the tie rule in [`predicates`](crate::evaluator::exact::predicates)). A
//! point set without its box's corners goes through `spade` and the same flips instead.
//!
//! Layout (after delaunator): triangle `t` owns half-edges `3t, 3t+1, 3t+2`; half-edge `e` runs
//! from `vertices[e]` to `vertices[next(e)]`; `twin[e]` is the opposite half-edge or [`NONE`] on
//! the grid border. Triangles are counter-clockwise (x right, y up).

use crate::evaluator::exact::predicates::{self, GridPoint, Lattice};
use spade::{DelaunayTriangulation, Point2, Triangulation as _};

/// Spade triangulates the points sheared to (x + y·SHEAR, y). Why: grid points are very often
/// co-circular, and each such tie sends spade's in-circle test down its slow exact path; the
/// shear breaks the ties (it is exact in f64 for sides up to 2¹⁴ and keeps every orientation
/// sign, so spade still returns a triangulation of the real points), and [`Triangulation::legalize_all`]'s
/// flips with the exact tie rule then reach the one canonical triangulation, as they would from
/// any triangulation.
pub const SHEAR: f64 = 1.0 / 1024.0;

/// "No half-edge": the twin of a border edge.
pub const NONE: u32 = u32::MAX;

/// The next half-edge of the same triangle.
#[inline]
pub fn next(e: u32) -> u32 {
    if e % 3 == 2 { e - 2 } else { e + 1 }
}

/// The previous half-edge of the same triangle.
#[inline]
pub fn prev(e: u32) -> u32 {
    if e % 3 == 0 { e + 2 } else { e - 1 }
}

/// A half-edge of the mesh [`Triangulation::insert_all`] builds: its origin as coordinates and
/// as a grid index, and its twin. Why: with `vertices` and `twin` apart, each walk step and
/// in-circle test converted three or four grid indices to coordinates (a multiply, a shift, a
/// multiply and a subtraction each) and checked two arrays' bounds; here one load gives all
/// three.
#[derive(Clone, Copy, Debug, Default)]
struct Half {
    at: [i32; 2],
    v: u32,
    twin: u32,
}

impl Half {
    #[inline(always)]
    fn point(&self) -> GridPoint {
        self.at.map(i64::from)
    }
}

/// [`Triangulation::walk`] then [`Triangulation::insert_point`] on `halves`, step for step
/// (the same edges tried in the same order, the same slots, the same flips): inserts grid point
/// `p` at `at`, walking from triangle `start`, and returns a triangle with vertex `p`, or
/// `start` when `p` is a vertex already (skipped, as spade skips a repeat; the next walk starts
/// where it would have).
#[inline(always)]
fn insert_half(
    halves: &mut Vec<Half>,
    start: u32,
    p: u32,
    at: GridPoint,
    stack: &mut Vec<[u32; 3]>,
) -> u32 {
    let t = walk_half(halves, start, at);
    let base = 3 * t;
    let tri: [Half; 3] = halves[base as usize..base as usize + 3]
        .try_into()
        .expect("a triangle has three half-edges");
    if tri.iter().any(|h| h.v == p) {
        return start;
    }
    stack.clear();
    let [a, b, c] = tri.map(|h| h.point());
    let on_edge = if predicates::orient(a, b, at) == 0 {
        Some(base)
    } else if predicates::orient(b, c, at) == 0 {
        Some(base + 1)
    } else if predicates::orient(c, a, at) == 0 {
        Some(base + 2)
    } else {
        None
    };
    let new = Half {
        at: at.map(|c| c as i32),
        v: p,
        twin: NONE,
    };
    match on_edge {
        None => {
            // (a, b, c) becomes (a, b, p), (b, c, p), (c, a, p).
            let [ha, hb, hc] = tri;
            let (e0, e1, e2) = (base, base + 1, base + 2);
            let t1 = halves.len() as u32 / 3;
            let t2 = t1 + 1;
            let (f1, f2) = (3 * t1, 3 * t2);
            halves[e1 as usize].twin = f1 + 2;
            halves[e2 as usize] = Half {
                twin: f2 + 1,
                ..new
            };
            halves.extend_from_slice(&[
                Half {
                    twin: hb.twin,
                    ..hb
                },
                Half { twin: f2 + 2, ..hc },
                Half { twin: e1, ..new },
                Half {
                    twin: hc.twin,
                    ..hc
                },
                Half { twin: e2, ..ha },
                Half {
                    twin: f1 + 1,
                    ..new
                },
            ]);
            relink(halves, hb.twin, f1);
            relink(halves, hc.twin, f2);
            stack.extend_from_slice(&[[e0, e1, e2], [f1, f1 + 1, f1 + 2], [f2, f2 + 1, f2 + 2]]);
        }
        Some(e) => {
            // On half-edge e = a → b of (a, b, c): that triangle becomes (a, p, c),
            // (p, b, c), and the neighbour (b, a, d), if any, becomes (b, p, d), (p, a, d).
            let f = halves[e as usize].twin;
            let t1 = split_half(halves, e, new);
            let t1 = 3 * t1;
            stack.extend_from_slice(&[[prev(e), e, next(e)], [t1 + 1, t1 + 2, t1]]);
            if f != NONE {
                let s1 = 3 * split_half(halves, f, new);
                halves[e as usize].twin = s1;
                halves[s1 as usize].twin = e;
                halves[f as usize].twin = t1;
                halves[t1 as usize].twin = f;
                stack.extend_from_slice(&[[prev(f), f, next(f)], [s1 + 1, s1 + 2, s1]]);
            }
        }
    }
    while let Some(edge) = stack.pop() {
        if let Some([pe, nf]) = flip_half(halves, edge) {
            stack.push(pe);
            stack.push(nf);
        }
    }
    t
}

/// [`Triangulation::walk`] on `halves` (uncapped steps would only loop on a broken mesh, so the
/// same cap).
#[inline(always)]
fn walk_half(halves: &[Half], start: u32, p: GridPoint) -> u32 {
    let mut t = start;
    let mut came_from = NONE;
    for _ in 0..=2 * halves.len() / 3 + 8 {
        let base = 3 * t as usize;
        // A slice of three (one bounds check), read in place (a copy went through the stack).
        let tri = &halves[base..base + 3];
        let (a, b, c) = (tri[0].point(), tri[1].point(), tri[2].point());
        let crosses = |k: usize, from: GridPoint, to: GridPoint| {
            base as u32 + k as u32 != came_from
                && predicates::orient(from, to, p) < 0
                && tri[k].twin != NONE
        };
        let k = if crosses(0, a, b) {
            0
        } else if crosses(1, b, c) {
            1
        } else if crosses(2, c, a) {
            2
        } else {
            return t;
        };
        came_from = tri[k].twin;
        t = came_from / 3;
    }
    panic!("a walk on a Delaunay triangulation ends");
}

/// Sets the twin of `e` (if any) to `to`.
#[inline(always)]
fn relink(halves: &mut [Half], e: u32, to: u32) {
    if e != NONE {
        halves[e as usize].twin = to;
    }
}

/// [`Triangulation::split_at_edge`] on `halves`, with `p` the new vertex (its twin unused).
#[inline(always)]
fn split_half(halves: &mut Vec<Half>, e: u32, p: Half) -> u32 {
    let (ne, pe) = (next(e), prev(e));
    let hb = halves[ne as usize];
    let hc = halves[pe as usize];
    let t1 = halves.len() as u32 / 3;
    halves[ne as usize] = Half {
        twin: 3 * t1 + 2,
        ..p
    };
    halves.extend_from_slice(&[
        Half { twin: NONE, ..p },
        Half {
            twin: hb.twin,
            ..hb
        },
        Half { twin: ne, ..hc },
    ]);
    relink(halves, hb.twin, 3 * t1 + 1);
    t1
}

/// (`next(e)`, `prev(e)`) from one remainder and two table look-ups (fewer instructions than
/// the two selects).
#[inline(always)]
fn next_prev(e: u32) -> (u32, u32) {
    let r = e % 3;
    let base = e - r;
    (base + [1, 2, 0][r as usize], base + [2, 0, 1][r as usize])
}

/// [`Triangulation::flip_if_illegal`] on `halves` of half-edge `e` given as `[e, next(e),
/// prev(e)]`; returns the two outer half-edges of the flipped quadrilateral opposite the new
/// diagonal's end `c` (what an insertion checks next), in the same form. Why the triples: the
/// caller always knows them, and each `next`/`prev` pair costs a division by 3 (a multiply and
/// half a dozen more instructions) on every test.
#[inline(always)]
fn flip_half(halves: &mut [Half], [e, ne, pe]: [u32; 3]) -> Option<[[u32; 3]; 2]> {
    let f = halves[e as usize].twin;
    if f == NONE {
        return None;
    }
    let (nf, pf) = next_prev(f);
    // Only the coordinates before the test, the rest after it (two in three tests flip
    // nothing): with all four half-edges live across the test, most of them were spilled to
    // the stack on every test.
    let at = |i: u32| halves[i as usize].point();
    let det = predicates::in_circle_det([at(e), at(ne), at(pe), at(pf)]);
    if det < 0 || (det == 0 && !tie_half(halves, [e, ne, pe, pf])) {
        return None;
    }
    let [he, hne, hpe, hpf] = [e, ne, pe, pf].map(|i| halves[i as usize]);
    // Triangles (u, w, c) and (w, u, d) become (d, c, u) and (c, d, w).
    let (x1, x2, y1, y2) = (hne.twin, hpe.twin, halves[nf as usize].twin, hpf.twin);
    halves[e as usize] = Half { twin: f, ..hpf };
    halves[ne as usize] = Half { twin: x2, ..hpe };
    halves[pe as usize] = Half { twin: y1, ..he };
    halves[f as usize] = Half { twin: e, ..hpe };
    halves[nf as usize] = Half { twin: y2, ..hpf };
    halves[pf as usize] = Half { twin: x1, ..hne };
    relink(halves, x2, ne);
    relink(halves, y1, pe);
    relink(halves, y2, nf);
    relink(halves, x1, pf);
    Some([[pe, e, ne], [nf, pf, f]])
}

/// [`predicates::in_circle`] of the half-edges `[e, next(e), prev(e), prev(twin(e))]` when
/// their points are co-circular: the tie rule, out of line.
#[inline(never)]
fn tie_half(halves: &[Half], edges: [u32; 4]) -> bool {
    let h = edges.map(|i| halves[i as usize]);
    predicates::in_circle(h.map(|h| h.point()), h.map(|h| h.v))
}

/// The order in which [`Triangulation::insert_all`] inserts a point set: groups of points, each
/// inserted in turn, alternately forwards and backwards.
///
/// In three rounds of rows (every fourth row, then the rows halfway between, then the rest).
/// Why: one sweep up the grid keeps inserting points just above a front whose triangles fan
/// out to the box's top corners, and each insertion then flips much of that fan; the rounds
/// fill in between rows already there, so each point takes fewer flips and in-circle tests
/// (for slightly longer walks).
///
/// Within a round, a dense set goes row by row (a group per row). A sparse one goes by bands of
/// `c` rows (`c` a power of two, chosen so that a `c`×`c` cell holds about four points) and
/// within a band cell by cell (a group per band), so the next point is about one cell away
/// rather than a whole row's gap: at 2 % kept a row's points are ≈ 50 columns apart, and the
/// walk between them crosses many thin triangles; bands halve the walk steps there. Denser
/// sets gain nothing from bands, so sets denser than about one point per 8×8 cell (c < 8,
/// about 12 % kept) keep the rows. The bands come from a counting sort, stable, so a cell's
/// points stay in row order.
#[derive(Clone, Debug, Default)]
pub(crate) struct InsertionOrder {
    /// The points in insertion order (unused when the groups index `kept` itself).
    points: Vec<u32>,
    /// Each group as a range of the points.
    groups: Vec<(u32, u32)>,
    /// Row-by-row scratch: each row as a range of `kept` and its round.
    rows: Vec<(u32, u32, u8)>,
    /// Counting-sort scratch: a count, then an offset, per key.
    counts: Vec<u32>,
    /// Counting-sort scratch: each point's key.
    keys: Vec<u32>,
}

impl InsertionOrder {
    /// Cells hold about this many points (see the type's docs).
    const POINTS_PER_CELL: f64 = 4.0;
    /// Bands of fewer rows than this (denser sets) go row by row.
    const MIN_BAND: u32 = 3;

    /// The round of row `y`.
    #[inline]
    fn round_of(y: i64) -> usize {
        match y & 3 {
            0 => 0,
            2 => 1,
            _ => 2,
        }
    }

    /// Plans the insertion of `kept` (increasing grid indices, repeats allowed), whose bounding
    /// box is `[x0, y0, x1, y1]`: the sequence of points and the ranges of its groups, in
    /// insertion order.
    pub(crate) fn plan<'a>(
        &'a mut self,
        lattice: Lattice,
        kept: &'a [u32],
        [x0, y0, x1, y1]: [i64; 4],
    ) -> (&'a [u32], &'a [(u32, u32)]) {
        self.groups.clear();
        let area = ((x1 - x0 + 1) * (y1 - y0 + 1)) as f64;
        let cell = (Self::POINTS_PER_CELL * area / kept.len().max(1) as f64).sqrt();
        let band = cell.max(1.0).log2().round() as u32;
        if band < Self::MIN_BAND {
            // Row by row: the rows are runs of one y in `kept`.
            self.rows.clear();
            let mut start = 0;
            while start < kept.len() {
                let y = lattice.point(kept[start])[1];
                let mut end = start + 1;
                while end < kept.len() && lattice.point(kept[end])[1] == y {
                    end += 1;
                }
                self.rows
                    .push((start as u32, end as u32, Self::round_of(y) as u8));
                start = end;
            }
            for round in 0..3 {
                let rows = self.rows.iter().filter(|r| r.2 == round);
                self.groups
                    .extend(rows.map(|&(start, end, _)| (start, end)));
            }
            return (kept, &self.groups);
        }
        // By bands and cells: key = (round, band, cell column), sorted by counting.
        let band = band.min(30);
        let columns = ((x1 - x0) >> band) as usize + 1;
        let bands = ((y1 - y0) >> band) as usize + 1;
        let keys = 3 * bands * columns;
        self.counts.clear();
        self.counts.resize(keys + 1, 0);
        self.keys.clear();
        for &p in kept {
            let [x, y] = lattice.point(p);
            let key = (Self::round_of(y) * bands + ((y - y0) >> band) as usize) * columns
                + ((x - x0) >> band) as usize;
            self.keys.push(key as u32);
            self.counts[key + 1] += 1;
        }
        for k in 1..=keys {
            self.counts[k] += self.counts[k - 1];
        }
        self.points.clear();
        self.points.resize(kept.len(), 0);
        for (&p, &key) in kept.iter().zip(&self.keys) {
            let slot = &mut self.counts[key as usize];
            self.points[*slot as usize] = p;
            *slot += 1;
        }
        // Now `counts[k]` is where key k's points end; a group is one (round, band).
        let mut begin = 0;
        for g in 0..3 * bands {
            let end = self.counts[(g + 1) * columns - 1];
            if end > begin {
                self.groups.push((begin, end));
            }
            begin = end;
        }
        (&self.points, &self.groups)
    }
}

/// A triangulation of grid points in half-edge form.
#[derive(Debug, Default)]
pub struct Triangulation {
    /// Grid index of the origin of each half-edge; three per triangle.
    pub vertices: Vec<u32>,
    /// Opposite half-edge, or `NONE`.
    pub twin: Vec<u32>,
    lattice: Lattice,
    stack: Vec<u32>,
    /// Scratch: our half-edge for each of spade's directed edges.
    slot: Vec<u32>,
    /// Scratch: spade's reversed directed edge for each of our half-edges.
    rev: Vec<u32>,
    /// Scratch of [`insert_all`](Self::insert_all): the order the points go in.
    order: InsertionOrder,
    /// Scratch of [`insert_all`](Self::insert_all): the mesh being built.
    halves: Vec<Half>,
    /// Scratch of [`insert_all`](Self::insert_all): half-edges to test, as `[e, next(e),
    /// prev(e)]`.
    flips: Vec<[u32; 3]>,
}

impl Clone for Triangulation {
    /// The triangles and their links (scratch buffers start empty).
    fn clone(&self) -> Self {
        let mut copy = Self::default();
        copy.clone_from(self);
        copy
    }

    /// Reuses this triangulation's buffers (the derived one would reallocate).
    fn clone_from(&mut self, source: &Self) {
        copy_fitted(&mut self.vertices, &source.vertices);
        copy_fitted(&mut self.twin, &source.twin);
        self.lattice = source.lattice;
    }
}

/// Makes `v` empty with room for `len` elements and not much more: a new buffer when its own
/// is too small or over twice too large. Why: the scorer's pooled meshes take turns holding
/// meshes of a few triangles and of thousands; grown by doubling, each would keep room for the
/// largest it ever held, twice over, and the pool would hold several times the memory its
/// meshes use.
pub(crate) fn fit<T>(v: &mut Vec<T>, len: usize) {
    if v.capacity() < len || v.capacity() > 2 * len + 256 {
        *v = Vec::with_capacity(len + len / 8 + 64);
    }
    v.clear();
}

/// `dst` made a copy of `src`, in a buffer [`fit`] for it.
pub(crate) fn copy_fitted<T: Copy>(dst: &mut Vec<T>, src: &[T]) {
    fit(dst, src.len());
    dst.extend_from_slice(src);
}

impl Triangulation {
    /// Empties `self` for triangles of points on a grid `width` wide, to be filled by hand
    /// (scratch buffers kept).
    pub(crate) fn clear_for(&mut self, width: usize) {
        self.lattice = Lattice::new(width);
        self.vertices.clear();
        self.twin.clear();
    }

    /// Frees the scratch buffers of a build (the triangles stay), for a mesh that is kept but
    /// not built into again.
    pub(crate) fn drop_scratch(&mut self) {
        self.stack = Vec::new();
        self.slot = Vec::new();
        self.rev = Vec::new();
        self.order = InsertionOrder::default();
        self.halves = Vec::new();
        self.flips = Vec::new();
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.vertices.len() / 3
    }

    /// True when there is no triangle.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Triangle `t` as three grid indices, counter-clockwise.
    pub fn triangle(&self, t: usize) -> [u32; 3] {
        [
            self.vertices[3 * t],
            self.vertices[3 * t + 1],
            self.vertices[3 * t + 2],
        ]
    }

    /// All triangles as grid-index triples.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        (0..self.len()).map(|t| self.triangle(t)).collect()
    }

    #[inline]
    fn point(&self, index: u32) -> GridPoint {
        self.lattice.point(index)
    }

    /// Rebuilds `self` as the canonical Delaunay triangulation of `kept` (grid indices on a grid
    /// `width` wide, distinct, at least three of them not collinear; increasing order is the
    /// fastest).
    ///
    /// When `kept` holds the four corners of its bounding box (the evaluator always keeps the
    /// grid's corners), the points are inserted one by one into the box's two triangles
    /// ([`insert_all`](Self::insert_all)); otherwise spade builds it
    /// ([`rebuild_with_spade`](Self::rebuild_with_spade)). Both give the same triangles.
    pub fn rebuild_delaunay(&mut self, width: usize, kept: &[u32]) {
        if !self.insert_all(width, kept) {
            self.rebuild_with_spade(width, kept);
        }
    }

    /// Rebuilds `self` as the canonical Delaunay triangulation of `kept` (as
    /// [`rebuild_delaunay`](Self::rebuild_delaunay)) with spade's bulk load and exact
    /// legalisation: the general path, and an independent cross-check of
    /// [`insert_all`](Self::insert_all).
    pub fn rebuild_with_spade(&mut self, width: usize, kept: &[u32]) {
        self.lattice = Lattice::new(width);
        // Plain points: a grid index is recovered exactly from its integer coordinates.
        let points: Vec<Point2<f64>> = kept
            .iter()
            .map(|&index| {
                let [x, y] = self.lattice.point(index);
                Point2::new(x as f64 + y as f64 * SHEAR, y as f64)
            })
            .collect();
        let dt = DelaunayTriangulation::<Point2<f64>>::bulk_load(points)
            .expect("grid coordinates are small finite integers");
        let faces = dt.num_inner_faces();
        self.vertices.clear();
        self.twin.clear();
        self.rev.clear();
        self.slot.clear();
        self.slot.resize(dt.num_directed_edges(), NONE);
        self.vertices.reserve(3 * faces);
        let w = width as u32;
        // One pass over spade's faces records vertices, where each directed edge landed, and
        // each half-edge's reverse; a second pass over plain arrays links the twins.
        for face in dt.inner_faces() {
            for edge in face.adjacent_edges() {
                let p = edge.from().position();
                self.slot[edge.fix().index()] = self.vertices.len() as u32;
                self.vertices
                    .push(p.y as u32 * w + (p.x - p.y * SHEAR) as u32);
                self.rev.push(edge.fix().rev().index() as u32);
            }
        }
        let slot = &self.slot;
        self.twin.extend(self.rev.iter().map(|&r| slot[r as usize]));
        // Empty scratch keeps its capacity but makes a clone of the mesh cheap.
        self.slot.clear();
        self.rev.clear();
        self.legalize_all();
    }

    /// Builds the canonical Delaunay triangulation of `kept` by Lawson insertion: the two
    /// triangles of the points' bounding box, then each point located by a visibility walk,
    /// its triangle (or edge) split, and the edges opposite it flipped under the tie rule until
    /// legal. Returns false, changing nothing, unless `kept` holds the box's four corners.
    ///
    /// Why not spade: every point lands inside the box, so there is no hull to maintain; the
    /// predicates are exact integers; and the points go in an order (`InsertionOrder`) where
    /// each next point is usually a neighbour of the last, so walks are short.
    pub fn insert_all(&mut self, width: usize, kept: &[u32]) -> bool {
        let lattice = Lattice::new(width);
        let (mut x0, mut y0, mut x1, mut y1) = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
        for &i in kept {
            let [x, y] = lattice.point(i);
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        if kept.is_empty() || x0 == x1 || y0 == y1 {
            return false;
        }
        let w = width as i64;
        let index = |x: i64, y: i64| (y * w + x) as u32;
        // Counter-clockwise from the lower left.
        let corners = [index(x0, y0), index(x1, y0), index(x1, y1), index(x0, y1)];
        let is_corner = |i: u32| corners.contains(&i);
        let found = kept.iter().fold(0u8, |mask, i| {
            mask | corners.iter().position(|c| c == i).map_or(0, |k| 1 << k)
        });
        if found != 0b1111 {
            return false;
        }
        self.lattice = lattice;
        // (a, b, c) and (c, d, a), sharing the diagonal c → a / a → c (made legal below).
        let [a, b, c, d] = corners;
        let mut stack = std::mem::take(&mut self.flips);
        let mut order = std::mem::take(&mut self.order);
        let (points, groups) = order.plan(lattice, kept, [x0, y0, x1, y1]);
        // The insertion runs on `halves` (coordinates next to each vertex and twin), which
        // gives the same slots and links as `walk` and `insert_point` on `self` would; see
        // `Half`.
        let mut halves = std::mem::take(&mut self.halves);
        halves.clear();
        halves.reserve(6 * kept.len() + 6);
        let half = |v: u32, twin: u32| Half {
            at: lattice.point(v).map(|c| c as i32),
            v,
            twin,
        };
        halves.extend(
            [(a, NONE), (b, NONE), (c, 5), (c, NONE), (d, NONE), (a, 2)].map(|(v, t)| half(v, t)),
        );
        let _ = flip_half(&mut halves, [2, 0, 1]);
        let mut last = 0u32;
        for (k, &(start, end)) in groups.iter().enumerate() {
            let group = &points[start as usize..end as usize];
            let mut insert = |p: u32| {
                if !is_corner(p) {
                    last = insert_half(&mut halves, last, p, lattice.point(p), &mut stack);
                }
            };
            // Alternating directions: each group starts near where the last one ended.
            if k % 2 == 0 {
                group.iter().for_each(|&p| insert(p));
            } else {
                group.iter().rev().for_each(|&p| insert(p));
            }
        }
        self.vertices.clear();
        self.twin.clear();
        self.vertices.extend(halves.iter().map(|h| h.v));
        self.twin.extend(halves.iter().map(|h| h.twin));
        self.halves = halves;
        self.order = order;
        self.flips = stack;
        true
    }

    /// The triangle whose closed area holds `p`, by a visibility walk from the live triangle
    /// `start`: each step crosses an edge that has `p` strictly outside it. `None` after
    /// `max_steps` steps; on a Delaunay triangulation the walk cannot cycle (Edelsbrunner
    /// 1990), so a cap only guards a broken invariant.
    pub fn walk(&self, start: u32, p: GridPoint, max_steps: usize) -> Option<u32> {
        let mut t = start;
        let mut came_from = NONE;
        for _ in 0..=max_steps {
            let base = 3 * t;
            // The triangle's three corners converted once (each is the origin of one edge and
            // the end of another); the edges are tried in order, the first that has `p`
            // strictly outside it deciding the step.
            let [a, b, c] = self.triangle(t as usize).map(|v| self.point(v));
            let crosses = |e: u32, from: GridPoint, to: GridPoint| {
                e != came_from
                    && predicates::orient(from, to, p) < 0
                    && self.twin[e as usize] != NONE
            };
            let step = if crosses(base, a, b) {
                Some(base)
            } else if crosses(base + 1, b, c) {
                Some(base + 1)
            } else if crosses(base + 2, c, a) {
                Some(base + 2)
            } else {
                None
            };
            match step {
                None => return Some(t),
                Some(e) => {
                    came_from = self.twin[e as usize];
                    t = came_from / 3;
                }
            }
        }
        None
    }

    /// The first half-edge of the fan around the origin of half-edge `e`: rotating clockwise
    /// (from a half-edge to the next of its twin) until the grid border, where a border vertex's
    /// fan is open, or once around back to `e`.
    pub fn fan_start(&self, e: u32) -> u32 {
        let mut at = e;
        loop {
            let before = self.fan_prev(at);
            if before == NONE {
                return at;
            }
            if before == e {
                return e;
            }
            at = before;
        }
    }

    /// The half-edge before `e` counter-clockwise around their common origin (the next of
    /// `e`'s twin), or `NONE` past the border.
    pub fn fan_prev(&self, e: u32) -> u32 {
        let f = self.twin[e as usize];
        if f == NONE { NONE } else { next(f) }
    }

    /// The half-edge after `e` counter-clockwise around their common origin (the twin of `e`'s
    /// previous half-edge), or `NONE` past the border.
    pub fn fan_next(&self, e: u32) -> u32 {
        self.twin[prev(e) as usize]
    }

    /// The half-edges leaving the origin of half-edge `e`, one per triangle of its star,
    /// counter-clockwise from the fan's first ([`fan_start`](Self::fan_start)).
    pub fn fan(&self, e: u32) -> impl Iterator<Item = u32> + '_ {
        let first = self.fan_start(e);
        std::iter::successors(Some(first), move |&at| {
            let after = self.fan_next(at);
            (after != NONE && after != first).then_some(after)
        })
    }

    /// The half-edge of triangle `t` that leaves vertex `v`, if `v` is one of its vertices.
    pub fn leaving(&self, t: u32, v: u32) -> Option<u32> {
        (3 * t..3 * t + 3).find(|&e| self.vertices[e as usize] == v)
    }

    /// Grows `inside` (triangles already claimed) by a flood: every triangle reachable from
    /// them across half-edges that are neither on the border nor `wall`s, each appended once,
    /// when `claim` takes it (`claim` returns false for a triangle already claimed). Used to
    /// find the triangles of a sub-triangulation that lie in a region, from the region's
    /// boundary edges.
    pub(crate) fn flood(
        &self,
        inside: &mut Vec<u32>,
        wall: impl Fn(u32) -> bool,
        mut claim: impl FnMut(u32) -> bool,
    ) {
        let mut at = 0;
        while at < inside.len() {
            let t = inside[at];
            at += 1;
            for e in 3 * t..3 * t + 3 {
                let f = self.twin[e as usize];
                if f != NONE && !wall(e) && claim(f / 3) {
                    inside.push(f / 3);
                }
            }
        }
    }

    /// The step cap of a walk on this triangulation: more than any walk can need.
    pub fn walk_cap(&self) -> usize {
        2 * self.len() + 8
    }

    /// Inserts grid point `p` into triangle `t`, which holds it inside or on an edge (not at a
    /// vertex), and restores the Delaunay property: the triangle (and, for a point on an
    /// interior edge, its neighbour) is split, then the edges opposite `p` are flipped under the
    /// tie rule until all are legal. Because the tie rule is a consistent
    /// Simulation-of-Simplicity perturbation, the result is the canonical triangulation of the
    /// new point set. Calls `changed` with every triangle slot created or modified (possibly
    /// more than once); unchanged triangles keep their slots, new ones are appended. `stack` is
    /// scratch. Returns a triangle with vertex `p`.
    pub fn insert_point(
        &mut self,
        t: u32,
        p: u32,
        stack: &mut Vec<u32>,
        mut changed: impl FnMut(u32),
    ) -> u32 {
        stack.clear();
        let at = self.point(p);
        let base = 3 * t;
        let on_edge = (base..base + 3).find(|&e| {
            let a = self.point(self.vertices[e as usize]);
            let b = self.point(self.vertices[next(e) as usize]);
            predicates::orient(a, b, at) == 0
        });
        match on_edge {
            None => {
                // (a, b, c) becomes (a, b, p), (b, c, p), (c, a, p).
                let (e0, e1, e2) = (3 * t, 3 * t + 1, 3 * t + 2);
                let [a, b, c] = self.triangle(t as usize);
                let twin_bc = self.twin[e1 as usize];
                let twin_ca = self.twin[e2 as usize];
                self.vertices[e2 as usize] = p;
                let t1 = self.push([b, c, p]);
                let t2 = self.push([c, a, p]);
                self.link(3 * t1, twin_bc);
                self.link(3 * t2, twin_ca);
                self.link(e1, 3 * t1 + 2);
                self.link(3 * t1 + 1, 3 * t2 + 2);
                self.link(3 * t2 + 1, e2);
                [t, t1, t2].into_iter().for_each(&mut changed);
                stack.extend_from_slice(&[e0, 3 * t1, 3 * t2]);
            }
            Some(e) => {
                // On half-edge e = a → b of (a, b, c): that triangle becomes (a, p, c),
                // (p, b, c), and the neighbour (b, a, d), if any, becomes (b, p, d), (p, a, d).
                let f = self.twin[e as usize];
                let t1 = self.split_at_edge(e, p);
                changed(e / 3);
                changed(t1);
                stack.extend_from_slice(&[prev(e), 3 * t1 + 1]);
                if f != NONE {
                    let s1 = self.split_at_edge(f, p);
                    self.link(e, 3 * s1);
                    self.link(f, 3 * t1);
                    changed(f / 3);
                    changed(s1);
                    stack.extend_from_slice(&[prev(f), 3 * s1 + 1]);
                }
            }
        }
        while let Some(e) = stack.pop() {
            if let Some([_, pe, nf, _]) = self.flip_if_illegal(e) {
                // After the flip, `pe` and `nf` are the two edges opposite the new point.
                changed(pe / 3);
                changed(nf / 3);
                stack.push(pe);
                stack.push(nf);
            }
        }
        // Slot t keeps vertex p through the split and every flip of its edges.
        t
    }

    /// Splits the triangle of half-edge `e` = a → b, (a, b, c), at `p` on that edge into
    /// (a, p, c), in place, and (p, b, c), appended; returns the new slot. The triangles are
    /// linked to each other and to c's side; `e` (now a → p) keeps its old twin, for the caller
    /// to relink.
    fn split_at_edge(&mut self, e: u32, p: u32) -> u32 {
        let (ne, pe) = (next(e), prev(e));
        let b = self.vertices[ne as usize];
        let c = self.vertices[pe as usize];
        let twin_bc = self.twin[ne as usize];
        self.vertices[ne as usize] = p;
        let t1 = self.push([p, b, c]);
        self.link(3 * t1 + 1, twin_bc);
        self.link(ne, 3 * t1 + 2);
        t1
    }

    /// Appends triangle `v` with no neighbours yet; returns its slot.
    fn push(&mut self, v: [u32; 3]) -> u32 {
        let t = (self.vertices.len() / 3) as u32;
        self.vertices.extend_from_slice(&v);
        self.twin.extend_from_slice(&[NONE; 3]);
        t
    }

    /// The coordinates of the grid the last rebuild was on.
    pub fn lattice(&self) -> Lattice {
        self.lattice
    }

    /// Flips every edge the tie rule calls illegal until none is left.
    pub fn legalize_all(&mut self) {
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        stack.extend((0..self.twin.len() as u32).filter(|&e| {
            let t = self.twin[e as usize];
            t != NONE && t > e
        }));
        while let Some(e) = stack.pop() {
            if let Some(outer) = self.flip_if_illegal(e) {
                stack.extend_from_slice(&outer);
            }
        }
        self.stack = stack;
    }

    /// Flips half-edge `e` if the tie rule calls it illegal; returns the four outer half-edges of
    /// the flipped quadrilateral, which need checking again.
    // Always inlined: as a call, its result goes through memory and its callers' loops (an
    // insertion's flips) pay the call on every edge.
    #[inline(always)]
    pub fn flip_if_illegal(&mut self, e: u32) -> Option<[u32; 4]> {
        let f = self.twin[e as usize];
        if f == NONE {
            return None;
        }
        let (ne, pe, nf, pf) = (next(e), prev(e), next(f), prev(f));
        let u = self.vertices[e as usize];
        let w = self.vertices[ne as usize];
        let c = self.vertices[pe as usize];
        let d = self.vertices[pf as usize];
        let pts = [self.point(u), self.point(w), self.point(c), self.point(d)];
        if !predicates::in_circle(pts, [u, w, c, d]) {
            return None;
        }
        // Triangles (u, w, c) and (w, u, d) become (d, c, u) and (c, d, w).
        let x1 = self.twin[ne as usize];
        let x2 = self.twin[pe as usize];
        let y1 = self.twin[nf as usize];
        let y2 = self.twin[pf as usize];
        let v = &mut self.vertices;
        v[e as usize] = d;
        v[ne as usize] = c;
        v[pe as usize] = u;
        v[f as usize] = c;
        v[nf as usize] = d;
        v[pf as usize] = w;
        self.link(e, f);
        self.link(ne, x2);
        self.link(pe, y1);
        self.link(nf, y2);
        self.link(pf, x1);
        Some([ne, pe, nf, pf])
    }

    #[inline]
    fn link(&mut self, a: u32, b: u32) {
        self.twin[a as usize] = b;
        if b != NONE {
            self.twin[b as usize] = a;
        }
    }
}

/// The half-edge of `mesh` from the origin of its half-edge `leaving` to `to`, by walking that
/// origin's fan from `leaving`: counter-clockwise, then, past the border, clockwise. (Not from
/// the fan's first half-edge, which for an inner vertex means walking the whole fan first: the
/// walk is a chain of dependent reads.)
pub(crate) fn edge_from(mesh: &Triangulation, leaving: u32, to: u32) -> Option<u32> {
    if leaving == NONE {
        return None;
    }
    let ends_at_to = |e: u32| mesh.vertices[next(e) as usize] == to;
    // Counter-clockwise, then clockwise (from the half-edge before `leaving`).
    for (step, start) in [
        (
            Triangulation::fan_next as fn(&Triangulation, u32) -> u32,
            leaving,
        ),
        (Triangulation::fan_prev, mesh.fan_prev(leaving)),
    ] {
        let mut at = start;
        while at != NONE {
            if ends_at_to(at) {
                return Some(at);
            }
            at = step(mesh, at);
            if at == leaving {
                // Once around an inner vertex: no such edge.
                return None;
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::mesh::canonical_form::canonical as rotate_min_first;
    use crate::evaluator::test_grids::random_subset;
    use rand::{RngExt, SeedableRng};

    /// [`Triangulation::insert_all`] as it reads with `walk` and `insert_point` on the half-edge
    /// arrays (the points in the same order and directions).
    fn insert_all_by_steps(mesh: &mut Triangulation, width: usize, kept: &[u32]) {
        let lattice = Lattice::new(width);
        let points: Vec<GridPoint> = kept.iter().map(|&i| lattice.point(i)).collect();
        let x0 = points.iter().map(|p| p[0]).min().unwrap();
        let x1 = points.iter().map(|p| p[0]).max().unwrap();
        let y0 = points.iter().map(|p| p[1]).min().unwrap();
        let y1 = points.iter().map(|p| p[1]).max().unwrap();
        let index = |x: i64, y: i64| (y * width as i64 + x) as u32;
        let [a, b, c, d] = [index(x0, y0), index(x1, y0), index(x1, y1), index(x0, y1)];
        mesh.lattice = lattice;
        mesh.vertices = vec![a, b, c, c, d, a];
        mesh.twin = vec![NONE, NONE, 5, NONE, NONE, 2];
        let _ = mesh.flip_if_illegal(2);
        let mut plan = InsertionOrder::default();
        let (order, groups) = plan.plan(lattice, kept, [x0, y0, x1, y1]);
        let (mut last, mut stack) = (0, Vec::new());
        for (k, &(start, end)) in groups.iter().enumerate() {
            let mut group = order[start as usize..end as usize].to_vec();
            if k % 2 == 1 {
                group.reverse();
            }
            for p in group {
                if [a, b, c, d].contains(&p) {
                    continue;
                }
                let t = mesh.walk(last, lattice.point(p), mesh.walk_cap()).unwrap();
                if !mesh.triangle(t as usize).contains(&p) {
                    last = mesh.insert_point(t, p, &mut stack, |_| {});
                }
            }
        }
    }

    #[test]
    fn insertion_on_halves_takes_the_same_steps() {
        // Random subsets (sparse to full, with repeats and points on the box's border) of grids
        // and of boxes inside them: the same slots, rotations and links, not only the same
        // triangles.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x7a11);
        for round in 0..300 {
            let (w, h) = (
                2 + rng.random_range(0..40usize),
                2 + rng.random_range(0..40usize),
            );
            let fraction = [0.02, 0.1, 0.3, 0.8, 1.0][round % 5];
            let (x0, y0) = (rng.random_range(0..w / 2), rng.random_range(0..h / 2));
            let (x1, y1) = (rng.random_range(x0 + 1..w), rng.random_range(y0 + 1..h));
            let mut kept: Vec<u32> = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
                .iter()
                .map(|&(x, y)| (y * w + x) as u32)
                .collect();
            for y in y0..=y1 {
                for x in x0..=x1 {
                    if rng.random::<f64>() < fraction {
                        kept.push((y * w + x) as u32);
                    }
                }
            }
            kept.sort_unstable();
            if round % 7 == 0 {
                kept.push(kept[kept.len() / 2]);
                kept.sort_unstable();
            }
            let mut fast = Triangulation::default();
            assert!(fast.insert_all(w, &kept));
            let mut steps = Triangulation::default();
            insert_all_by_steps(&mut steps, w, &kept);
            assert_eq!(fast.vertices, steps.vertices, "round {round}");
            assert_eq!(fast.twin, steps.twin, "round {round}");
        }
    }

    #[test]
    fn insertion_order_takes_every_point_once_by_rows_or_by_bands() {
        // A dense set goes row by row: each group one row of `kept`, rounds y ≡ 0, 2, then odd
        // (mod 4). A sparse one goes by bands: each group one band of rows in one round, its
        // cells left to right, and row order kept within a cell. Either way every point (repeats
        // included) comes exactly once.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x0bde);
        let (w, h) = (257usize, 200usize);
        let lattice = Lattice::new(w);
        // The band (log₂ of the cell side) each density gets: cells of about four points.
        for (fraction, band) in [(0.02, Some(4)), (0.05, Some(3)), (0.3, None), (1.0, None)] {
            let mut kept: Vec<u32> = (0..(w * h) as u32)
                .filter(|_| rng.random::<f64>() < fraction)
                .collect();
            kept.push(kept[kept.len() / 3]);
            kept.sort_unstable();
            let mut plan = InsertionOrder::default();
            let (points, groups) = plan.plan(lattice, &kept, [0, 0, w as i64 - 1, h as i64 - 1]);
            let mut sequence: Vec<u32> = groups
                .iter()
                .flat_map(|&(s, e)| points[s as usize..e as usize].iter().copied())
                .collect();
            assert_eq!(sequence.len(), kept.len(), "{fraction}");
            let round = |p: u32| InsertionOrder::round_of(lattice.point(p)[1]);
            let rounds: Vec<usize> = sequence.iter().map(|&p| round(p)).collect();
            assert!(rounds.is_sorted(), "{fraction}: rounds in order");
            let rows_of = |&(s, e): &(u32, u32)| -> Vec<i64> {
                let mut ys: Vec<i64> = points[s as usize..e as usize]
                    .iter()
                    .map(|&p| lattice.point(p)[1])
                    .collect();
                ys.dedup();
                ys
            };
            if let Some(band) = band {
                assert!(groups.windows(2).all(|g| g[0].1 == g[1].0), "{fraction}");
                for g in groups {
                    let ys = rows_of(g);
                    let bands: Vec<i64> = ys.iter().map(|y| y >> band).collect();
                    assert!(bands.iter().all(|&b| b == bands[0]), "{fraction}: one band");
                }
                assert!(
                    groups.iter().any(|g| rows_of(g).len() > 1),
                    "{fraction}: a group spans several rows"
                );
                for &(s, e) in groups {
                    let xs: Vec<i64> = points[s as usize..e as usize]
                        .iter()
                        .map(|&p| lattice.point(p)[0] >> band)
                        .collect();
                    assert!(xs.is_sorted(), "{fraction}: cells left to right");
                }
            } else {
                assert!(groups.iter().all(|g| rows_of(g).len() == 1), "{fraction}");
            }
            sequence.sort_unstable();
            assert_eq!(sequence, kept, "{fraction}: every point once");
        }
    }

    /// The triangulation depends on the point set only, not on the order it is given in.
    #[test]
    fn triangulation_ignores_insertion_order() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(9);
        // A 9×9 grid with every point kept is full of co-circular squares: a stress test for ties.
        let width = 9;
        for fraction in [1.0, 0.5, 0.25] {
            let mut kept: Vec<u32> = random_subset(81, fraction, &mut rng);
            kept.extend([0, 8, 72, 80]);
            kept.sort_unstable();
            kept.dedup();
            let mut canonical = Triangulation::default();
            canonical.rebuild_delaunay(width, &kept);
            let mut expected = canonical
                .triangles()
                .into_iter()
                .map(rotate_min_first)
                .collect::<Vec<_>>();
            expected.sort_unstable();
            for _ in 0..5 {
                let mut shuffled = kept.clone();
                for i in (1..shuffled.len()).rev() {
                    shuffled.swap(i, rng.random_range(0..=i));
                }
                let mut t = Triangulation::default();
                t.rebuild_delaunay(width, &shuffled);
                let mut got = t
                    .triangles()
                    .into_iter()
                    .map(rotate_min_first)
                    .collect::<Vec<_>>();
                got.sort_unstable();
                assert_eq!(got, expected, "fraction {fraction}");
            }
        }
    }

    /// Lawson insertion ([`Triangulation::insert_all`], what the evaluator uses) and spade's bulk
    /// load with legalisation ([`Triangulation::rebuild_with_spade`]) are independent algorithms:
    /// they must give the same canonical triangles on every point set, from sparse to the full grid
    /// (full of co-circular squares), with points on the box's border, and on a box smaller than the
    /// grid. Without the box's four corners, `insert_all` declines and the spade path is taken.
    #[test]
    fn insertion_and_spade_build_the_same_triangulation() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(21);
        let canonical = |t: &Triangulation| {
            let mut v: Vec<_> = t.triangles().into_iter().map(rotate_min_first).collect();
            v.sort_unstable();
            v
        };
        for (width, height) in [(2usize, 2usize), (9, 9), (17, 5), (33, 33), (65, 40)] {
            let n = width * height;
            for fraction in [0.0, 0.03, 0.1, 0.3, 0.7, 1.0] {
                // The whole grid's box, then a box from (1, 1) to (width − 2, height − 1) when the
                // grid is big enough: its corners kept, only points inside it.
                let mut boxes = vec![(0, 0, width - 1, height - 1)];
                if width > 3 && height > 3 {
                    boxes.push((1, 1, width - 2, height - 1));
                }
                for (x0, y0, x1, y1) in boxes {
                    let inside = |i: u32| {
                        let (x, y) = (i as usize % width, i as usize / width);
                        (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
                    };
                    let mut kept: Vec<u32> = random_subset(n, fraction, &mut rng)
                        .into_iter()
                        .filter(|&i| inside(i))
                        .collect();
                    kept.extend(
                        [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
                            .map(|(x, y)| (y * width + x) as u32),
                    );
                    kept.sort_unstable();
                    kept.dedup();
                    let (mut by_insertion, mut by_spade) =
                        (Triangulation::default(), Triangulation::default());
                    assert!(by_insertion.insert_all(width, &kept));
                    by_spade.rebuild_with_spade(width, &kept);
                    assert_eq!(
                        canonical(&by_insertion),
                        canonical(&by_spade),
                        "{width}×{height}, {fraction} kept, box {:?}",
                        (x0, y0, x1, y1)
                    );
                    // A repeated point changes nothing.
                    if let Some(&again) = kept.get(kept.len() / 2) {
                        let mut repeated = kept.clone();
                        repeated.push(again);
                        let mut with_repeat = Triangulation::default();
                        assert!(with_repeat.insert_all(width, &repeated));
                        assert_eq!(canonical(&with_repeat), canonical(&by_spade));
                    }
                    // Without a corner of its box the set is refused, and rebuild_delaunay falls
                    // back to spade.
                    if kept.len() > 4 {
                        let without = &kept[1..];
                        assert!(!by_insertion.insert_all(width, without));
                        by_insertion.rebuild_delaunay(width, without);
                        by_spade.rebuild_with_spade(width, without);
                        assert_eq!(canonical(&by_insertion), canonical(&by_spade));
                    }
                }
            }
        }
    }
}
