//! The canonical Delaunay triangulation of a set of grid points, as half-edge arrays.
//!
//! `spade` builds a Delaunay triangulation; co-circular ties are then settled by Lawson flips
//! under the project's tie rule ([`predicates::in_circle`]), which makes the result a function of
//! the point set alone (see the tie rule in [`predicates`]).
//!
//! Layout (after delaunator): triangle `t` owns half-edges `3t, 3t+1, 3t+2`; half-edge `e` runs
//! from `vertices[e]` to `vertices[next(e)]`; `twin[e]` is the opposite half-edge or [`NONE`] on
//! the grid border. Triangles are counter-clockwise (x right, y up).

use super::predicates::{self, GridPoint};
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation as _};

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

struct Vertex {
    position: Point2<f64>,
    index: u32,
}

impl HasPosition for Vertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.position
    }
}

/// A triangulation of grid points in half-edge form.
#[derive(Clone, Debug, Default)]
pub struct Triangulation {
    /// Grid index of the origin of each half-edge; three per triangle.
    pub vertices: Vec<u32>,
    /// Opposite half-edge, or [`NONE`].
    pub twin: Vec<u32>,
    width: i64,
    stack: Vec<u32>,
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
        let i = index as i64;
        [i % self.width, i / self.width]
    }

    /// Rebuilds `self` as the canonical Delaunay triangulation of `kept` (grid indices on a grid
    /// `width` wide, distinct, at least three of them not collinear).
    pub fn rebuild_delaunay(&mut self, width: usize, kept: &[u32]) {
        self.width = width as i64;
        let w = self.width;
        let points: Vec<Vertex> = kept
            .iter()
            .map(|&index| Vertex {
                position: Point2::new((index as i64 % w) as f64, (index as i64 / w) as f64),
                index,
            })
            .collect();
        let dt = DelaunayTriangulation::<Vertex>::bulk_load(points)
            .expect("grid coordinates are small finite integers");
        let faces = dt.num_inner_faces();
        self.vertices.clear();
        self.twin.clear();
        self.vertices.reserve(3 * faces);
        self.twin.resize(3 * faces, NONE);
        // Slot of every directed edge of spade's in our half-edge arrays.
        let mut slot = vec![NONE; dt.num_directed_edges()];
        for (t, face) in dt.inner_faces().enumerate() {
            for (k, edge) in face.adjacent_edges().iter().enumerate() {
                self.vertices.push(edge.from().data().index);
                slot[edge.fix().index()] = (3 * t + k) as u32;
            }
        }
        for face in dt.inner_faces() {
            for edge in face.adjacent_edges() {
                let here = slot[edge.fix().index()];
                self.twin[here as usize] = slot[edge.rev().fix().index()];
            }
        }
        self.legalize_all();
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
