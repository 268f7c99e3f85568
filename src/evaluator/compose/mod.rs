//! Scoring a crossed child by composing its two parents' meshes.
//!
//! An orthogonal-array child takes each grid point's gene from one of two parents A and B,
//! block by block: its kept set is A's on the points labelled A and B's on those labelled B.
//! Most of its canonical triangulation is already in the parents' meshes, with every error
//! rasterised: [`Evaluator::compose`](crate::evaluator::Evaluator::compose) keeps those triangles and
//! their errors, and triangulates and rasterises only what is new along the seams between the
//! blocks.
//!
//! Why it is exact: under the tie rule (a Simulation of Simplicity, see
//! [`predicates`](crate::evaluator::exact::predicates)) a triangle belongs to the canonical triangulation of a
//! point set exactly when its vertices are in the set and no other point of the set is inside
//! its (perturbed) circumcircle. A triangle of A whose vertices the child keeps has no point of
//! A inside its circle, so only the child's points labelled B can spoil it; those are looked up
//! inside the circle's grid box (and there are none in most boxes, which a summed-area table of
//! the labels tells in four reads). Each kept triangle is taken from the parent its smallest
//! vertex's label names, so none is taken twice. Whatever the taken triangles do not cover (the
//! region R) is tiled by the child's other triangles, which are those of the canonical
//! triangulation of R's points that lie in R (as for a region removal in
//! [`edit`](crate::evaluator::edit)). A taken triangle owns the same grid points with the
//! same errors as in its parent, so only R's triangles are rasterised.
//!
//! The children of one orthogonal-array crossover share their parents and their blocks, and
//! differ only in which parent gives each block. [`PartClasses`] classifies both parents'
//! triangles once against the blocks: each triangle gets the set of blocks whose labelling for
//! the other parent would drop it, so each child's classification is a mask test per triangle
//! ([`Evaluator::compose_parts`](crate::evaluator::Evaluator::compose_parts)) instead of a summed-area
//! lookup and a circle search.

mod crossing;
mod part_classes;
mod spoiling;

pub use crossing::Crossing;
pub use part_classes::PartClasses;
pub(crate) use spoiling::{counted_in, next_stamp, overlap};

use crate::evaluator::exact::fixed_point::ErrorTotals;
use crate::evaluator::exact::predicates::Lattice;
use crate::evaluator::mesh::canonical_triangulation::{NONE, edge_from, fit};
use crate::evaluator::mesh::disc_box::DiscBox;
use crate::evaluator::mesh::region::{BOUNDARY, Region};
use crate::evaluator::mesh::state::MeshState;
use crate::evaluator::raster::triangle_memo::TriangleMemo;
use crate::evaluator::score::Score;
use crate::heightfield::Heightfield;
use spoiling::{MAX_SEARCHED_BOX, spoils};
use std::sync::Arc;

/// Scratch buffers of [`Evaluator::compose`](crate::evaluator::Evaluator::compose), kept between calls.
#[derive(Clone, Debug, Default)]
pub(crate) struct ComposeScratch {
    /// Summed-area table of the B labels, `(W + 1) × (H + 1)`.
    sat: Vec<u32>,
    /// Per grid point: 1 when labelled B.
    labels: Vec<u8>,
    /// Per slot of A and of B: its slot in the child, or [`NONE`] when not taken.
    map: [Vec<u32>; 2],
    /// The taken slots of A, then of B.
    taken: [Vec<u32>; 2],
    /// Half-edges of taken triangles with R across: (child half-edge, from, to).
    open: Vec<(u32, u32, u32)>,
    /// Per grid point: listed in `points`.
    listed: Vec<bool>,
    /// R's points and the grid corners.
    points: Vec<u32>,
    /// R's triangles (the tags of its boundary edges are the child's half-edges across).
    region: Region,
    /// Per grid point: the stamp of the last composition one of whose taken triangles has it.
    covered: Vec<u32>,
    stamp: u32,
    /// R's slots whose totals the memo did not know.
    unknown: Vec<(u32, [u32; 3])>,
}

/// Where a child's labels come from: a bitset over the grid (bit set: from B), or parts of
/// a [`PartClasses`] with a level per part (bit `part` set: from B).
#[derive(Clone, Copy)]
enum Labels<'a> {
    Bits(&'a [u64]),
    Parts(&'a PartClasses, u32),
}

impl MeshState {
    /// Makes `self` the scored mesh of the child that keeps `a`'s kept points where `from_b`
    /// is clear and `b`'s where it is set (`from_b` a bitset over the grid indices, bit `i` of
    /// word `i / 64`), reusing the parents' triangles and errors. The score is bit for bit the
    /// fresh evaluation's. Returns `None`, with `self` unscored, when `a` and `b` are not both
    /// scored on `hf` with their disc boxes filled ([`ensure_discs`](Self::ensure_discs)), or
    /// when a guard fails; the caller then scores the child another way.
    pub(crate) fn compose(
        &mut self,
        hf: &Arc<Heightfield>,
        a: &MeshState,
        b: &MeshState,
        from_b: &[u64],
        scratch: &mut ComposeScratch,
    ) -> Option<Score> {
        self.compose_with(hf, [a, b], Labels::Bits(from_b), scratch, None)
    }

    /// [`compose`](Self::compose) for the child of `crossing` that takes each part from B
    /// where bit `part` of `levels` is set and from A elsewhere, with both parents' triangles
    /// classified once for all such children ([`PartClasses::new`]). The same mesh and bits as
    /// [`compose`](Self::compose) with the equivalent bitset. Returns `None`, with `self`
    /// unscored, also when the classification was not made for the parents.
    pub(crate) fn compose_parts(
        &mut self,
        crossing: Crossing<'_>,
        levels: u32,
        scratch: &mut ComposeScratch,
        memo: &mut TriangleMemo,
    ) -> Option<Score> {
        self.compose_with(
            crossing.hf,
            crossing.parents,
            Labels::Parts(crossing.classes, levels),
            scratch,
            Some(memo),
        )
    }

    /// Composes the child of `parents` that `source` labels: marks its kept points, takes the
    /// parents' triangles it keeps, and tiles and rasterises the region R they leave.
    fn compose_with(
        &mut self,
        hf: &Arc<Heightfield>,
        parents: [&MeshState; 2],
        source: Labels<'_>,
        scratch: &mut ComposeScratch,
        memo: Option<&mut TriangleMemo>,
    ) -> Option<Score> {
        self.score = None;
        self.hf = None;
        self.revision = 0;
        let [a, b] = parents;
        let (w, h, n) = (hf.width(), hf.height(), hf.len());
        let labels_fit = match source {
            Labels::Bits(from_b) => from_b.len() >= n.div_ceil(64),
            Labels::Parts(classes, _) => classes.is_for(a, b) && classes.part.len() == n,
        };
        if !labels_fit || !a.is_composable_on(hf) || !b.is_composable_on(hf) {
            return None;
        }
        let vertices = self.label_child(parents, source, scratch, w, h);
        // The child's triangle count, by Euler: a triangulation of the grid rectangle with V
        // vertices, B of them on its border, has 2V − B − 2 triangles. It sizes the child's
        // arrays, and guards the reasoning below (a leak or a gap would change the count).
        let on_border = (0..w)
            .flat_map(|x| [x, (h - 1) * w + x])
            .chain((1..h - 1).flat_map(|y| [y * w, y * w + w - 1]))
            .filter(|&i| self.kept[i])
            .count();
        let expected = (2 * vertices).checked_sub(on_border + 2)? as u32;
        let taken = choose_taken(parents, &self.kept, source, scratch, w);
        if taken == 0 {
            // Nothing to reuse (say, a corners-only parent whose corner 0 is labelled B): the
            // child is built from scratch.
            let kept: Vec<u32> = (0..n as u32).filter(|&i| self.kept[i as usize]).collect();
            let score = self.rebuild(hf, &kept);
            self.ensure_discs();
            return Some(score);
        }
        let stamp = self.copy_taken(parents, scratch, w, n, expected, taken);
        list_region_points(&self.kept, scratch, stamp, n);
        let open_len = scratch.open.len();
        if open_len == 0 {
            // Nothing is new: the parents' triangles tile the grid (or the guard fails).
            if taken != expected || !scratch.points.is_empty() {
                return None;
            }
        } else {
            self.tile_region(hf, scratch, memo, taken, expected)?;
        }
        self.hf = Some(hf.clone());
        let score = self.finish(hf);
        self.discs_valid = true;
        Some(score)
    }

    /// Writes the child's kept marks and, for a bitset, each grid point's label and the
    /// labels' summed-area table (B labels in columns < x of rows < y at (y, x)), in one pass;
    /// returns the child's number of kept points.
    fn label_child(
        &mut self,
        parents: [&MeshState; 2],
        source: Labels<'_>,
        scratch: &mut ComposeScratch,
        w: usize,
        h: usize,
    ) -> usize {
        // Each entry is written once, in order: pushed, rather than zeroed first and then
        // overwritten (a second pass over the grid per composition).
        self.kept.clear();
        scratch.labels.clear();
        let sw = w + 1;
        scratch.sat.clear();
        let mut vertices = 0usize;
        match source {
            Labels::Bits(from_b) => {
                scratch.sat.resize(sw, 0);
                for y in 0..h {
                    let mut row = 0;
                    scratch.sat.push(0);
                    for x in 0..w {
                        let i = y * w + x;
                        let l = ((from_b[i / 64] >> (i % 64)) & 1) as u8;
                        scratch.labels.push(l);
                        let k = parents[l as usize].kept[i];
                        self.kept.push(k);
                        vertices += usize::from(k);
                        row += u32::from(l);
                        let below = scratch.sat[y * sw + x + 1];
                        scratch.sat.push(below + row);
                    }
                }
            }
            Labels::Parts(classes, levels) => {
                // Part by part, row by row: copies of the labelled parent's kept marks (the
                // parts' labels decide which triangles are taken, so no label per point).
                self.kept.resize(w * h, false);
                for (p, &[x0, y0, x1, y1]) in classes.rects.iter().enumerate() {
                    let l = (levels >> p) & 1;
                    let from = &parents[l as usize].kept;
                    for y in y0..y1 {
                        let row = y * w + x0..y * w + x1;
                        self.kept[row.clone()].copy_from_slice(&from[row]);
                    }
                }
                vertices = self.kept.iter().map(|&k| usize::from(k)).sum();
            }
        }
        vertices
    }

    /// Copies the taken triangles (numbered by [`choose_taken`]), linked to each other where
    /// they meet, with their disc boxes and totals; lists the half-edges with R across and
    /// points each vertex's hint at one of its triangles. Returns the stamp that marks the
    /// points of taken triangles in `scratch.covered`.
    fn copy_taken(
        &mut self,
        parents: [&MeshState; 2],
        scratch: &mut ComposeScratch,
        w: usize,
        n: usize,
        expected: u32,
        taken: u32,
    ) -> u32 {
        // The taken slots were numbered parent by parent in slot order, so each parent's taken
        // triangles fill a run of the child's arrays in order (cheaper than a push per entry).
        let room = expected.max(taken) as usize;
        let taken = taken as usize;
        self.hint.resize(n, 0);
        let stamp = next_stamp(&mut scratch.stamp, &mut scratch.covered, n);
        self.mesh.clear_for(w);
        fit(&mut self.mesh.vertices, 3 * room);
        self.mesh.vertices.resize(3 * taken, 0);
        fit(&mut self.mesh.twin, 3 * room);
        self.mesh.twin.resize(3 * taken, NONE);
        fit(&mut self.discs, room);
        self.discs.resize(taken, DiscBox::default());
        fit(&mut self.totals, room);
        self.totals.resize(taken, ErrorTotals::default());
        scratch.open.clear();
        let hints = &mut self.hint;
        let covered = &mut scratch.covered;
        let mut first_slot = 0;
        for side in 0..2 {
            let (parent, other) = (parents[side], parents[1 - side]);
            let (map, other_map) = (&scratch.map[side], &scratch.map[1 - side]);
            let list = &scratch.taken[side];
            let range = first_slot..first_slot + list.len();
            let (from_vertices, from_twins) = (&parent.mesh.vertices, &parent.mesh.twin);
            let child_vertices =
                self.mesh.vertices[3 * range.start..3 * range.end].chunks_exact_mut(3);
            let child_twins = self.mesh.twin[3 * range.start..3 * range.end].chunks_exact_mut(3);
            let rows = list.iter().zip(child_vertices.zip(child_twins));
            for (slot, (&t, (vertices, twins))) in (range.start as u32..).zip(rows) {
                let src = 3 * t as usize;
                let tri = &from_vertices[src..src + 3];
                vertices.copy_from_slice(tri);
                for &v in tri {
                    hints[v as usize] = slot;
                    covered[v as usize] = stamp;
                }
                for (k, (twin, &g)) in twins.iter_mut().zip(&from_twins[src..src + 3]).enumerate() {
                    *twin = if g == NONE {
                        NONE
                    } else if map[(g / 3) as usize] != NONE {
                        3 * map[(g / 3) as usize] + g % 3
                    } else {
                        let (u, v) = (tri[k], tri[(k + 1) % 3]);
                        twin_in(other, other_map, v, u).unwrap_or_else(|| {
                            scratch.open.push((3 * slot + k as u32, u, v));
                            NONE
                        })
                    };
                }
            }
            for (dst, &t) in self.discs[range.clone()].iter_mut().zip(list) {
                *dst = parent.discs[t as usize];
            }
            for (dst, &t) in self.totals[range.clone()].iter_mut().zip(list) {
                *dst = parent.totals[t as usize];
            }
            first_slot = range.end;
        }
        debug_assert_eq!(self.totals.len(), taken);
        stamp
    }

    /// Tiles R with its triangles, wrapped from its boundary (see [`region`](crate::evaluator::mesh::region)), after the
    /// `taken` ones, linked inside R and across its boundary, and rasterises them. `None` when
    /// the count is not the `expected` one.
    fn tile_region(
        &mut self,
        hf: &Arc<Heightfield>,
        scratch: &mut ComposeScratch,
        memo: Option<&mut TriangleMemo>,
        taken: u32,
        expected: u32,
    ) -> Option<()> {
        let (w, h) = (hf.width(), hf.height());
        let lattice = Lattice::new(w);
        let region = &mut scratch.region;
        region.wrap(w, h, &scratch.points, &scratch.open)?;
        let next_new = taken + region.triangles.len() as u32;
        if next_new != expected {
            debug_assert!(false, "composed {next_new} triangles, not {expected}");
            return None;
        }
        for (t, tri) in region.triangles.iter().enumerate() {
            let slot = taken + t as u32;
            self.mesh.vertices.extend_from_slice(tri);
            for k in 0..3 {
                let twin = region.twins[3 * t + k];
                let twin = if twin == NONE {
                    NONE
                } else if twin & BOUNDARY != 0 {
                    let outer = scratch.open[(twin & !BOUNDARY) as usize].0;
                    self.mesh.twin[outer as usize] = 3 * slot + k as u32;
                    outer
                } else {
                    3 * taken + twin
                };
                self.mesh.twin.push(twin);
            }
            let p = tri.map(|i| lattice.point(i));
            self.discs.push(DiscBox::of(p, w, h));
        }
        self.totals
            .resize(next_new as usize, ErrorTotals::default());
        match memo {
            Some(memo) => self.rasterise_with_memo(hf, taken..next_new, memo, &mut scratch.unknown),
            None => self.rasterise(hf, taken..next_new),
        }
        Some(())
    }
}

/// Decides which triangles of each parent the child takes: fills `scratch.map` (per parent
/// slot, its child slot or [`NONE`]) and `scratch.taken` (the taken slots, per parent), and
/// returns how many are taken. Parent A's are numbered first, then B's, each in slot order.
#[allow(clippy::needless_range_loop)] // slots and grid indices index several arrays at once
fn choose_taken(
    parents: [&MeshState; 2],
    child_kept: &[bool],
    source: Labels<'_>,
    scratch: &mut ComposeScratch,
    w: usize,
) -> u32 {
    let labels = &scratch.labels;
    let label = |i: u32| u64::from(labels[i as usize]);
    let kept_in_child = |i: u32| child_kept[i as usize];
    let lattice = Lattice::new(w);
    let sat = &scratch.sat;
    let labelled_b = |d: &DiscBox| counted_in(sat, w, d.rect()) as usize;
    let mut next_slot = 0u32;
    for side in 0..2 {
        let parent = parents[side];
        let m = &parent.mesh;
        let (map, taken) = (&mut scratch.map[side], &mut scratch.taken[side]);
        map.clear();
        map.resize(m.len(), NONE);
        taken.clear();
        if let Labels::Parts(classes, levels) = source {
            // The parts labelled for the other parent; a triangle is taken when the part
            // of its smallest vertex is labelled for this one and none of its kill parts
            // is labelled for the other (see `PartClasses`).
            // (A classification has one to 32 parts.)
            let all = u32::MAX >> (32 - classes.rects.len());
            let other = if side == 0 { levels } else { !levels } & all;
            let (first, kill) = (&classes.first[side], &classes.kill[side]);
            // Without branches: which triangles a row takes follows the blocks, which the
            // slot order does not.
            taken.resize(m.len(), 0);
            let mut count = 0usize;
            for (t, (&f, &k)) in first.iter().zip(kill).enumerate() {
                let take = ((other >> f) & 1 == 0) & (k & other == 0);
                map[t] = if take { next_slot + count as u32 } else { NONE };
                taken[count] = t as u32;
                count += usize::from(take);
            }
            taken.truncate(count);
            next_slot += count as u32;
            continue;
        }
        for t in 0..m.len() {
            let tri = m.triangle(t);
            let first = tri[0].min(tri[1]).min(tri[2]);
            if label(first) as usize != side || !tri.iter().all(|&v| kept_in_child(v)) {
                continue;
            }
            let disc = &parent.discs[t];
            let b_points = labelled_b(disc);
            let other = if side == 0 {
                b_points
            } else {
                disc.area() - b_points
            };
            let keep = other == 0
                || (disc.area() <= MAX_SEARCHED_BOX
                    && !spoils(tri, disc.rect(), lattice, w, |i| {
                        label(i as u32) != side as u64 && kept_in_child(i as u32)
                    }));
            if keep {
                map[t] = next_slot;
                next_slot += 1;
                taken.push(t as u32);
            }
        }
    }
    next_slot
}

/// Lists R's points in `scratch.points`: the kept points no taken triangle has (their
/// `covered` entry is not `stamp`), then the ends of the half-edges with R across.
fn list_region_points(kept: &[bool], scratch: &mut ComposeScratch, stamp: u32, n: usize) {
    scratch.listed.resize(n, false);
    scratch.points.clear();
    for (i, (&k, &c)) in kept.iter().zip(scratch.covered.iter()).enumerate() {
        if k && c != stamp {
            scratch.listed[i] = true;
            scratch.points.push(i as u32);
        }
    }
    for j in 0..scratch.open.len() {
        let (_, u, v) = scratch.open[j];
        for p in [u, v] {
            if !std::mem::replace(&mut scratch.listed[p as usize], true) {
                scratch.points.push(p);
            }
        }
    }
    for &p in &scratch.points {
        scratch.listed[p as usize] = false;
    }
}

/// The child's half-edge `from → to` when it is an edge of a triangle taken from `parent`
/// (`map` its taken slots).
fn twin_in(parent: &MeshState, map: &[u32], from: u32, to: u32) -> Option<u32> {
    if !parent.kept[from as usize] || !parent.kept[to as usize] {
        return None;
    }
    let t = parent.hint[from as usize];
    let m = &parent.mesh;
    let e = edge_from(m, m.leaving(t, from)?, to)?;
    let slot = map[(e / 3) as usize];
    (slot != NONE).then(|| 3 * slot + e % 3)
}
