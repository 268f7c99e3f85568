//! The canonical Delaunay triangulation of a set of grid points, as half-edge arrays.
//!
//! `spade` builds a Delaunay triangulation; co-circular ties are then settled by Lawson flips
//! under the project's tie rule ([`predicates::in_circle`]), which makes the result a function of
//! the point set alone (see the tie rule in [`predicates`]).
//!
//! Layout (after delaunator): triangle `t` owns half-edges `3t, 3t+1, 3t+2`; half-edge `e` runs
//! from `vertices[e]` to `vertices[next(e)]`; `twin[e]` is the opposite half-edge or [`NONE`] on
//! the grid border. Triangles are counter-clockwise (x right, y up).

use super::predicates::{self, GridPoint, Lattice};
use spade::{DelaunayTriangulation, Point2, Triangulation as _};

/// Spade triangulates the points sheared to (x + y·SHEAR, y). Why: grid points are very often
/// co-circular, and each such tie sends spade's in-circle test down its slow exact path; the
/// shear breaks the ties (it is exact in f64 for sides up to 2¹⁴ and keeps every orientation
/// sign, so spade still returns a triangulation of the real points), and [`Triangulation::legalize_all`]'s
/// flips with the exact tie rule then reach the one canonical triangulation, as they would from
/// any triangulation. Measured: a fresh evaluation 23 % faster at 30 % kept on a 65×65 grid.
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

/// A triangulation of grid points in half-edge form.
#[derive(Debug, Default)]
pub struct Triangulation {
    /// Grid index of the origin of each half-edge; three per triangle.
    pub vertices: Vec<u32>,
    /// Opposite half-edge, or [`NONE`].
    pub twin: Vec<u32>,
    lattice: Lattice,
    stack: Vec<u32>,
    /// Scratch: our half-edge for each of spade's directed edges.
    slot: Vec<u32>,
    /// Scratch: spade's reversed directed edge for each of our half-edges.
    rev: Vec<u32>,
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
        self.vertices.clone_from(&source.vertices);
        self.twin.clone_from(&source.twin);
        self.lattice = source.lattice;
    }
}

impl Triangulation {
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
    /// `width` wide, distinct, at least three of them not collinear).
    pub fn rebuild_delaunay(&mut self, width: usize, kept: &[u32]) {
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
