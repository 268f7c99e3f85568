//! A crossover child's mutant scored without a mesh: the child's region R, changed by the
//! mutation's few points.
//!
//! Why it is exact: as for the child itself ([`compose`](crate::evaluator::compose)), a reused
//! triangle stays in the mutant's canonical triangulation exactly when its vertices are all
//! kept and no kept point is inside its circle, so it goes exactly when it has a removed
//! vertex or an inserted point inside its circle (under the tie rule). Those are found in each
//! parent's mesh: a removed point's star, and an inserted point's *cavity* (the triangles
//! whose circles hold it, which form a connected set around the triangle holding it in any
//! Delaunay triangulation). Whatever the remaining reused triangles leave uncovered, R grown
//! by the dropped triangles, is tiled as before ([`Region::wrap`](crate::evaluator::mesh::region::Region::wrap)).
//!
//! Why bother: a mutant usually differs from its crossed child in a gene or two, and most
//! mutants die at the next survival; building the crossed child's mesh only to edit it would
//! cost about as much as scoring all of a crossover's children.

use super::shared::{
    ChangeScratch, Changes, PartScores, RowScratch, class_of, on_grid_border, score_from_scratch,
    score_of,
};
use crate::evaluator::compose::Crossing;
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::exact::predicates::{Lattice, in_circle};
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::mesh::canonical_triangulation::{NONE, next};
use crate::evaluator::mesh::state::MeshState;
use crate::evaluator::score::Score;
use crate::heightfield::Heightfield;

impl PartScores {
    /// Turns R (`scratch.points`, `scratch.open`) and the reused triangles' `totals` and count
    /// of the child with the classes `scratch.taken` into the mutant's (see the module docs).
    /// `None` when a parent's mesh is not as its classification says.
    pub(crate) fn change(
        &self,
        crossing: Crossing<'_>,
        changes: Changes<'_>,
        scratch: &mut RowScratch,
        totals: &mut ErrorTotals,
        taken_count: &mut u32,
    ) -> Option<()> {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        let lattice = Lattice::new(hf.width());
        let RowScratch {
            taken,
            listed,
            points,
            open,
            changes: work,
            ..
        } = scratch;
        let reused = |side: usize, t: u32| {
            taken[class_of(classes, &self.special, side, t as usize) as usize]
        };
        find_dropped(parents, lattice, changes, work, reused)?;
        self.drop_totals(crossing, taken, work, totals, taken_count);
        // R's boundary: a dropped triangle's edge with R across is inside R now; one with a
        // remaining reused triangle across is on R's boundary, seen from that triangle; one
        // with another dropped triangle across is inside; one on the grid border stays there.
        for &(side, t) in &work.dropped {
            let m = &parents[side].mesh;
            for e in 3 * t..3 * t + 3 {
                if m.twin[e as usize] == NONE {
                    continue;
                }
                let (u, v) = (m.vertices[e as usize], m.vertices[next(e) as usize]);
                let across_dropped = work.dropped.iter().any(|&(s, d)| {
                    let dm = &parents[s].mesh;
                    (3 * d..3 * d + 3)
                        .any(|f| dm.vertices[f as usize] == v && dm.vertices[next(f) as usize] == u)
                });
                if across_dropped {
                    continue;
                }
                match open.iter().position(|&(_, a, b)| a == u && b == v) {
                    Some(i) => {
                        open.swap_remove(i);
                    }
                    None => open.push((0, v, u)),
                }
            }
            // Its vertices are R's now (the removed ones aside, taken out below).
            for v in m.triangle(t as usize) {
                list(listed, points, v);
            }
        }
        for &q in changes.inserted {
            list(listed, points, q);
        }
        for &p in changes.removed {
            listed[p as usize] = false;
        }
        points.retain(|p| !changes.removed.contains(p));
        Some(())
    }

    /// Takes the dropped triangles (`work.dropped`) out of the reused triangles' `totals` and
    /// count. A sum subtracts; a maximum is made again from the classes, each recomputed
    /// without its dropped triangles where one of them may have held it.
    fn drop_totals(
        &self,
        crossing: Crossing<'_>,
        taken: &[bool],
        work: &mut ChangeScratch,
        totals: &mut ErrorTotals,
        taken_count: &mut u32,
    ) {
        let Crossing {
            parents, classes, ..
        } = crossing;
        work.classes.clear();
        for &(side, t) in &work.dropped {
            let own = &parents[side].totals[t as usize];
            totals.sum -= own.sum;
            totals.sum_sq -= own.sum_sq;
            *taken_count -= 1;
            let c = class_of(classes, &self.special, side, t as usize);
            if own.max >= self.classes[c as usize].totals.max && !work.classes.contains(&c) {
                work.classes.push(c);
            }
        }
        let mut max = 0.0f64;
        for (c, class) in self.classes.iter().enumerate() {
            if !taken[c] {
                continue;
            }
            let class_max = if work.classes.contains(&(c as u32)) {
                let side = usize::from(class.side);
                let parent = parents[side];
                (0..parent.mesh.len() as u32)
                    .filter(|&t| {
                        class_of(classes, &self.special, side, t as usize) == c as u32
                            && !work.dropped.contains(&(side, t))
                    })
                    .map(|t| parent.totals[t as usize].max)
                    .fold(0.0, f64::max)
            } else {
                class.totals.max
            };
            max = if class_max > max { class_max } else { max };
        }
        totals.max = max;
    }
}

/// Lists in `work.dropped` the reused triangles (`reused`) that `changes` drop: a removed
/// point's star, in each parent that keeps it, and an inserted point's cavity, in each parent
/// that does not (in one that does, no circle holds it). `None` when a parent's mesh is not
/// as its hints say.
fn find_dropped(
    parents: [&MeshState; 2],
    lattice: Lattice,
    changes: Changes<'_>,
    work: &mut ChangeScratch,
    reused: impl Fn(usize, u32) -> bool,
) -> Option<()> {
    work.dropped.clear();
    for &p in changes.removed {
        for (side, parent) in parents.into_iter().enumerate() {
            if !parent.kept[p as usize] {
                continue;
            }
            let m = &parent.mesh;
            let first = m.leaving(parent.hint[p as usize], p)?;
            for e in m.fan(first) {
                let t = e / 3;
                if reused(side, t) && !work.dropped.contains(&(side, t)) {
                    work.dropped.push((side, t));
                }
            }
        }
    }
    for &q in changes.inserted {
        for (side, parent) in parents.into_iter().enumerate() {
            if parent.kept[q as usize] {
                continue;
            }
            let dropped = &mut work.dropped;
            let (seen, queue) = (&mut work.seen, &mut work.queue);
            cavity(parent, lattice, q, [seen, queue], |t| {
                if reused(side, t) && !dropped.contains(&(side, t)) {
                    dropped.push((side, t));
                }
            });
        }
    }
    Some(())
}

/// Adds grid point `p` to R's `points` unless `listed` says it is there already.
fn list(listed: &mut [bool], points: &mut Vec<u32>, p: u32) {
    if !std::mem::replace(&mut listed[p as usize], true) {
        points.push(p);
    }
}

/// Calls `visit` on each triangle of `state`'s mesh whose circle holds grid point `q` (not
/// kept; under the tie rule): its cavity, connected around the triangle that holds `q`, found by
/// a walk there and a breadth-first search (`seen` and `queue` are scratch).
fn cavity(
    state: &MeshState,
    lattice: Lattice,
    q: u32,
    [seen, queue]: [&mut Vec<u32>; 2],
    mut visit: impl FnMut(u32),
) {
    let m = &state.mesh;
    let at = lattice.point(q);
    let start = state.locate(lattice, start_near(state, q), at);
    seen.clear();
    queue.clear();
    seen.push(start);
    queue.push(start);
    while let Some(t) = queue.pop() {
        let tri = m.triangle(t as usize);
        let p = tri.map(|i| lattice.point(i));
        if !in_circle([p[0], p[1], p[2], at], [tri[0], tri[1], tri[2], q]) {
            continue;
        }
        visit(t);
        for e in 3 * t..3 * t + 3 {
            let g = m.twin[e as usize];
            if g != NONE && !seen.contains(&(g / 3)) {
                seen.push(g / 3);
                queue.push(g / 3);
            }
        }
    }
}

/// A triangle slot near grid point `q` in `parent`'s mesh, to start a walk to it from: of the
/// kept point nearest before it in index order (usually on its row), else after it.
fn start_near(parent: &MeshState, q: u32) -> u32 {
    let bits = &parent.kept_bits;
    let (word, bit) = ((q / 64) as usize, q % 64);
    let below = bits[word] & ((1u64 << bit) - 1);
    if below != 0 {
        return parent.hint[64 * word + 63 - below.leading_zeros() as usize];
    }
    if let Some(w) = (0..word).rev().find(|&w| bits[w] != 0) {
        return parent.hint[64 * w + 63 - bits[w].leading_zeros() as usize];
    }
    // Corner 0 is kept: only a bad index gets here.
    parent.hint[0]
}

/// The score of the mesh that `base` (a scored mesh on `hf`) becomes with `changes` made to its
/// kept points, without changing `base` or building that mesh: bit for bit what an
/// [`edit`](crate::evaluator::Evaluator::edit) of a copy (and a fresh evaluation) gives. Every
/// triangle of `base` is reused but those the changes drop (as for a crossover child's mutant,
/// see the module docs); they are R, which is tiled and rasterised. `None` when `base`'s
/// lookups are stale ([`MeshState::ensure_discs`]), when a removed point is a corner or not
/// kept, an inserted one is kept or out of range, or a guard fails (score it another way).
pub(crate) fn score_mutant(
    hf: &std::sync::Arc<Heightfield>,
    base: &MeshState,
    changes: Changes<'_>,
    scratch: &mut RowScratch,
) -> Option<Score> {
    let (w, h, n) = (hf.width(), hf.height(), hf.len());
    let base_score = base.score?;
    let same_field = base
        .hf
        .as_ref()
        .is_some_and(|f| std::sync::Arc::ptr_eq(f, hf));
    if !same_field || !base.lookup_valid || base.kept.len() < n {
        return None;
    }
    let expected = mutant_triangle_count(hf, base, base_score, changes)?;
    let lattice = Lattice::new(w);
    let m = &base.mesh;
    let RowScratch {
        listed,
        points,
        open,
        region,
        unknown,
        memo,
        changes: work,
        sub,
        ..
    } = scratch;
    drop_from_base(base, lattice, changes, work)?;
    if work.dropped.is_empty() {
        return (changes.removed.is_empty() && changes.inserted.is_empty()).then_some(base_score);
    }
    let mut totals = reused_base_totals(base, work);
    let reused = m.len() as i64 - work.dropped.len() as i64;
    // R's boundary: the dropped triangles' edges with a reused triangle across, seen from it
    // (R lies left of v → u); those on the grid border stay there.
    let is_dropped = |t: usize| work.dropped.iter().any(|&(_, d)| d as usize == t);
    listed.resize(n, false);
    points.clear();
    open.clear();
    for &(_, t) in &work.dropped {
        for e in 3 * t..3 * t + 3 {
            let g = m.twin[e as usize];
            if g != NONE && !is_dropped((g / 3) as usize) {
                let (u, v) = (m.vertices[e as usize], m.vertices[next(e) as usize]);
                open.push((0, v, u));
            }
        }
        for v in m.triangle(t as usize) {
            list(listed, points, v);
        }
    }
    for &q in changes.inserted {
        list(listed, points, q);
    }
    for &p in points.iter() {
        listed[p as usize] = false;
    }
    points.retain(|p| !changes.removed.contains(p));
    let units = ErrorUnits::of(hf);
    if open.is_empty() {
        // The changes drop every triangle (a sparse mesh on a small grid), and wrapping starts
        // from a boundary edge: the mutant is built from scratch.
        points.clear();
        points.extend((0..n as u32).filter(|&i| base.kept[i as usize]));
        points.retain(|p| !changes.removed.contains(p));
        points.extend_from_slice(changes.inserted);
        points.sort_unstable();
        return Some(score_from_scratch(hf, units, points, sub));
    }
    region.wrap(w, h, points, open)?;
    if reused + region.triangles.len() as i64 != expected {
        debug_assert!(false, "R's triangles do not complete the mutant");
        return None;
    }
    memo.prepare(Some(hf));
    let tris = region.triangles.iter().map(|&t| ((), canonical(t)));
    memo.sum_triangles(hf, tris, unknown, |_, t| totals.add(&t));
    Some(score_of(units, &totals, expected as u32, n))
}

/// Euler's count of the mutant's triangles, from the base's: 2V − B − 2. `None` when a removed
/// point is a corner, not kept or out of range, or an inserted one is kept or out of range.
fn mutant_triangle_count(
    hf: &Heightfield,
    base: &MeshState,
    base_score: Score,
    changes: Changes<'_>,
) -> Option<i64> {
    let n = hf.len();
    let corners = hf.corners();
    let on_border = |p: u32| i64::from(on_grid_border(hf, p));
    let mut expected = base_score.t as i64;
    for &p in changes.removed {
        if (p as usize) >= n || !base.kept[p as usize] || corners.contains(&p) {
            return None;
        }
        expected -= 2 - on_border(p);
    }
    for &q in changes.inserted {
        if (q as usize) >= n || base.kept[q as usize] {
            return None;
        }
        expected += 2 - on_border(q);
    }
    Some(expected)
}

/// Lists in `work.dropped` the triangles of `base` that `changes` drop: removed points' stars
/// and inserted points' cavities. `None` when a hint does not lead to a removed point.
fn drop_from_base(
    base: &MeshState,
    lattice: Lattice,
    changes: Changes<'_>,
    work: &mut ChangeScratch,
) -> Option<()> {
    let m = &base.mesh;
    work.dropped.clear();
    for &p in changes.removed {
        let first = m.leaving(base.hint[p as usize], p)?;
        for e in m.fan(first) {
            if !work.dropped.contains(&(0, e / 3)) {
                work.dropped.push((0, e / 3));
            }
        }
    }
    for &q in changes.inserted {
        let dropped = &mut work.dropped;
        cavity(base, lattice, q, [&mut work.seen, &mut work.queue], |t| {
            if !dropped.contains(&(0, t)) {
                dropped.push((0, t));
            }
        });
    }
    Some(())
}

/// The largest maximum among `base`'s triangles that are not dropped: the first of its
/// [`largest`](MeshState::largest) maxima that is not (every triangle outside that list has a
/// maximum no larger than its last), else a pass over the mesh.
fn next_maximum(base: &MeshState, is_dropped: &impl Fn(usize) -> bool) -> f64 {
    for &(max, slot) in &base.largest {
        if max <= 0.0 {
            // Padding: no other triangle has a nonzero maximum.
            return 0.0;
        }
        if !is_dropped(slot as usize) {
            return max;
        }
    }
    (base.totals[..base.mesh.len()].iter().enumerate())
        .filter(|&(t, _)| !is_dropped(t))
        .map(|(_, own)| own.max)
        .fold(0.0, f64::max)
}

/// The reused triangles' totals: all of the base's but the dropped ones (a sum over the base's
/// triangles is cheaper than the copy an edit needs). Sums subtract; the maximum is made again
/// without the dropped triangles only when one of them may have held it.
fn reused_base_totals(base: &MeshState, work: &ChangeScratch) -> ErrorTotals {
    let is_dropped = |t: usize| work.dropped.iter().any(|&(_, d)| d as usize == t);
    let all = &base.totals[..base.mesh.len()];
    // The mesh's own sum, less the dropped triangles' (exact integers): a cost per dropped
    // triangle, not per triangle of the mesh.
    let mut totals = base.all;
    let mut max_dropped = false;
    for &(_, t) in &work.dropped {
        let own = &all[t as usize];
        totals.sum -= own.sum;
        totals.sum_sq -= own.sum_sq;
        max_dropped |= own.max >= totals.max;
    }
    if max_dropped {
        totals.max = next_maximum(base, &is_dropped);
    }
    totals
}
