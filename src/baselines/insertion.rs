//! Incremental insertion of one grid point into a canonical Delaunay [`Triangulation`].
//!
//! The point must lie in (or on an edge of) a known triangle: greedy insertion always inserts a
//! point that a triangle owns, so no point location is needed. The triangle (and, for a point on
//! an interior edge, its neighbour) is split, then the edges opposite the new point are flipped
//! under the project's tie rule ([`Triangulation::flip_if_illegal`]) until all are legal. Because
//! the tie rule is a consistent Simulation-of-Simplicity perturbation, Lawson's insertion yields
//! the unique canonical triangulation of the new point set, the one the evaluator builds.

use crate::evaluator::predicates;
use crate::evaluator::triangulation::{NONE, Triangulation, next, prev};

/// Inserts grid point `p` into triangle `t` of `mesh` (on the grid it was built on). `p` must lie inside
/// `t` or on one of its edges, and not be one of its vertices. Appends to `changed` every
/// triangle slot that was created or modified (possibly with repeats); slots of unchanged
/// triangles keep their numbers, new triangles are appended.
pub(crate) fn insert_point(
    mesh: &mut Triangulation,
    t: u32,
    p: u32,
    stack: &mut Vec<u32>,
    changed: &mut Vec<u32>,
) {
    let lattice = mesh.lattice();
    let point = |i: u32| lattice.point(i);
    let pp = point(p);
    let base = 3 * t;
    stack.clear();
    let on_edge = (0..3).map(|k| base + k).find(|&e| {
        let a = mesh.vertices[e as usize];
        let b = mesh.vertices[next(e) as usize];
        predicates::orient(point(a), point(b), pp) == 0
    });
    match on_edge {
        None => split_triangle(mesh, t, p, stack, changed),
        Some(e) => split_edge(mesh, e, p, stack, changed),
    }
    while let Some(e) = stack.pop() {
        if let Some([_, pe, nf, _]) = mesh.flip_if_illegal(e) {
            // After the flip, `pe` and `nf` are the two edges opposite the new point.
            changed.push(pe / 3);
            changed.push(nf / 3);
            stack.push(pe);
            stack.push(nf);
        }
    }
}

fn link(mesh: &mut Triangulation, a: u32, b: u32) {
    mesh.twin[a as usize] = b;
    if b != NONE {
        mesh.twin[b as usize] = a;
    }
}

fn push_triangle(mesh: &mut Triangulation, v: [u32; 3]) -> u32 {
    let t = (mesh.vertices.len() / 3) as u32;
    mesh.vertices.extend_from_slice(&v);
    mesh.twin.extend_from_slice(&[NONE; 3]);
    t
}

/// `p` strictly inside triangle `t` = (a, b, c): it becomes (a, b, p), (b, c, p), (c, a, p).
fn split_triangle(
    mesh: &mut Triangulation,
    t: u32,
    p: u32,
    stack: &mut Vec<u32>,
    changed: &mut Vec<u32>,
) {
    let (e0, e1, e2) = (3 * t, 3 * t + 1, 3 * t + 2);
    let [a, b, c] = mesh.triangle(t as usize);
    let twin_bc = mesh.twin[e1 as usize];
    let twin_ca = mesh.twin[e2 as usize];
    mesh.vertices[e2 as usize] = p;
    let t1 = push_triangle(mesh, [b, c, p]);
    let t2 = push_triangle(mesh, [c, a, p]);
    link(mesh, 3 * t1, twin_bc);
    link(mesh, 3 * t2, twin_ca);
    link(mesh, e1, 3 * t1 + 2);
    link(mesh, 3 * t1 + 1, 3 * t2 + 2);
    link(mesh, 3 * t2 + 1, e2);
    changed.extend_from_slice(&[t, t1, t2]);
    stack.extend_from_slice(&[e0, 3 * t1, 3 * t2]);
}

/// `p` on half-edge `e` = a→b of triangle (a, b, c): that triangle becomes (a, p, c), (p, b, c),
/// and the neighbour across the edge, (b, a, d), if any, becomes (b, p, d), (p, a, d).
fn split_edge(
    mesh: &mut Triangulation,
    e: u32,
    p: u32,
    stack: &mut Vec<u32>,
    changed: &mut Vec<u32>,
) {
    let (ne, pe) = (next(e), prev(e));
    let b = mesh.vertices[ne as usize];
    let c = mesh.vertices[pe as usize];
    let f = mesh.twin[e as usize];
    let twin_bc = mesh.twin[ne as usize];
    // (a, b, c) → (a, p, c): e = a→p, ne = p→c, pe = c→a keeps its twin.
    mesh.vertices[ne as usize] = p;
    let t1 = push_triangle(mesh, [p, b, c]);
    link(mesh, 3 * t1 + 1, twin_bc);
    link(mesh, ne, 3 * t1 + 2);
    changed.extend_from_slice(&[e / 3, t1]);
    stack.extend_from_slice(&[pe, 3 * t1 + 1]);
    if f == NONE {
        mesh.twin[e as usize] = NONE;
        return;
    }
    let (nf, pf) = (next(f), prev(f));
    let a = mesh.vertices[nf as usize];
    let d = mesh.vertices[pf as usize];
    let twin_ad = mesh.twin[nf as usize];
    // (b, a, d) → (b, p, d): f = b→p, nf = p→d, pf = d→b keeps its twin.
    mesh.vertices[nf as usize] = p;
    let s1 = push_triangle(mesh, [p, a, d]);
    link(mesh, 3 * s1 + 1, twin_ad);
    link(mesh, nf, 3 * s1 + 2);
    link(mesh, e, 3 * s1);
    link(mesh, f, 3 * t1);
    changed.extend_from_slice(&[f / 3, s1]);
    stack.extend_from_slice(&[pf, 3 * s1 + 1]);
}
