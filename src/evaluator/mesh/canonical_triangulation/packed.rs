//! The insertion of [`Triangulation::insert_all`](super::Triangulation::insert_all) on packed
//! half-edges: the walk, the split and the Lawson flips under the tie rule, step for step as
//! [`Triangulation`](super::Triangulation)'s own methods do them on its arrays.

use super::{NONE, next, prev};
use crate::evaluator::exact::predicates::{self, GridPoint};

/// A half-edge of the mesh [`Triangulation::insert_all`] builds: its origin as coordinates and
/// as a grid index, and its twin. Why: with `vertices` and `twin` apart, each walk step and
/// in-circle test converted three or four grid indices to coordinates (a multiply, a shift, a
/// multiply and a subtraction each) and checked two arrays' bounds; here one load gives all
/// three.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Half {
    pub(super) at: [i32; 2],
    pub(super) v: u32,
    pub(super) twin: u32,
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
pub(super) fn insert_half(
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
pub(super) fn flip_half(halves: &mut [Half], [e, ne, pe]: [u32; 3]) -> Option<[[u32; 3]; 2]> {
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
