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
pub(crate) const SHEAR: f64 = 1.0 / 1024.0;

/// "No half-edge": the twin of a border edge.
pub(crate) const NONE: u32 = u32::MAX;

/// The next half-edge of the same triangle.
#[inline]
pub(crate) fn next(e: u32) -> u32 {
    if e % 3 == 2 { e - 2 } else { e + 1 }
}

/// The previous half-edge of the same triangle.
#[inline]
pub(crate) fn prev(e: u32) -> u32 {
    if e.is_multiple_of(3) { e + 2 } else { e - 1 }
}

mod insertion_order;
mod packed;
#[cfg(test)]
mod tests;

pub(crate) use insertion_order::InsertionOrder;
use packed::{Half, flip_half, insert_half};

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
    pub(crate) fn triangle(&self, t: usize) -> [u32; 3] {
        [
            self.vertices[3 * t],
            self.vertices[3 * t + 1],
            self.vertices[3 * t + 2],
        ]
    }

    /// All triangles as grid-index triples.
    pub(crate) fn triangles(&self) -> Vec<[u32; 3]> {
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
    /// (`insert_all`); otherwise spade builds it
    /// (`rebuild_with_spade`). Both give the same triangles.
    pub fn rebuild_delaunay(&mut self, width: usize, kept: &[u32]) {
        if !self.insert_all(width, kept) {
            self.rebuild_with_spade(width, kept);
        }
    }

    /// Rebuilds `self` as the canonical Delaunay triangulation of `kept` (as
    /// [`rebuild_delaunay`](Self::rebuild_delaunay)) with spade's bulk load and exact
    /// legalisation: the general path, and an independent cross-check of
    /// [`insert_all`](Self::insert_all).
    pub(crate) fn rebuild_with_spade(&mut self, width: usize, kept: &[u32]) {
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
    pub(crate) fn insert_all(&mut self, width: usize, kept: &[u32]) -> bool {
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
    pub(crate) fn walk(&self, start: u32, p: GridPoint, max_steps: usize) -> Option<u32> {
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
    pub(crate) fn fan_start(&self, e: u32) -> u32 {
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
    pub(crate) fn fan_prev(&self, e: u32) -> u32 {
        let f = self.twin[e as usize];
        if f == NONE { NONE } else { next(f) }
    }

    /// The half-edge after `e` counter-clockwise around their common origin (the twin of `e`'s
    /// previous half-edge), or `NONE` past the border.
    pub(crate) fn fan_next(&self, e: u32) -> u32 {
        self.twin[prev(e) as usize]
    }

    /// The half-edges leaving the origin of half-edge `e`, one per triangle of its star,
    /// counter-clockwise from the fan's first (`fan_start`).
    pub(crate) fn fan(&self, e: u32) -> impl Iterator<Item = u32> + '_ {
        let first = self.fan_start(e);
        std::iter::successors(Some(first), move |&at| {
            let after = self.fan_next(at);
            (after != NONE && after != first).then_some(after)
        })
    }

    /// The star of the origin v of half-edge `leaving`, as removing v needs it: its triangles,
    /// the boundary chain a₀ … aₖ counter-clockwise (triangle (v, aᵢ, aᵢ₊₁) gives the boundary
    /// edge aᵢ → aᵢ₊₁; a border vertex's chain is open, closed by a border segment) and each
    /// boundary edge's outer twin. The three lists are cleared first.
    pub(crate) fn star_of(
        &self,
        leaving: u32,
        star: &mut Vec<u32>,
        boundary: &mut Vec<u32>,
        outer: &mut Vec<u32>,
    ) {
        star.clear();
        boundary.clear();
        outer.clear();
        let start = self.fan_start(leaving);
        let mut e = start;
        loop {
            star.push(e / 3);
            let link = next(e);
            boundary.push(self.vertices[link as usize]);
            outer.push(self.twin[link as usize]);
            let back = self.fan_next(e);
            if back == NONE {
                boundary.push(self.vertices[prev(e) as usize]);
                return;
            }
            e = back;
            if e == start {
                return;
            }
        }
    }

    /// The half-edge of triangle `t` that leaves vertex `v`, if `v` is one of its vertices.
    pub(crate) fn leaving(&self, t: u32, v: u32) -> Option<u32> {
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
    pub(crate) fn walk_cap(&self) -> usize {
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
    pub(crate) fn insert_point(
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
    pub(crate) fn lattice(&self) -> Lattice {
        self.lattice
    }

    /// Flips every edge the tie rule calls illegal until none is left.
    pub(crate) fn legalize_all(&mut self) {
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
    pub(crate) fn flip_if_illegal(&mut self, e: u32) -> Option<[u32; 4]> {
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
