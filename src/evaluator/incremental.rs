//! A scored mesh that can be edited: remove and insert kept points, and get the score of the new
//! kept set bit for bit as a fresh [`Evaluator::score`](super::Evaluator::score) would give it.
//!
//! How, and why it is exact:
//! - The triangulation is the canonical Delaunay triangulation of the kept set (unique under the
//!   tie rule of [`predicates`]), so the triangulation reached by local edits is *the same set of
//!   triangles* as the one built from scratch. A removal deletes the vertex's star and fills the
//!   hole with the Delaunay triangles of its boundary (the baselines' `hole::fill`); an insertion
//!   locates the point by a visibility walk and splits and flips (the baselines'
//!   [`Triangulation::insert_point`]). Both restore the Delaunay property under the tie rule, so each
//!   intermediate mesh is canonical too.
//! - Every grid point's error comes from the one triangle that owns it ([`raster`](super::raster)),
//!   rasterised with its vertices in a canonical rotation (smallest grid index first), so a
//!   triangle gives the same bits whichever way it was created. The state keeps each triangle's
//!   error totals; a triangle that no edit touched owns the same points with the same totals as
//!   before, and only the touched triangles are rasterised again.
//! - The totals are exact fixed-point integers ([`errors`](super::errors)), so the mesh's score,
//!   their sum over its triangles, is the same in any order.
//!
//! Cost: an edit costs about its walk, its flips or hole fill, and the area of the triangles it
//! changed; a state costs ≈ 5 bytes per grid point plus 48 bytes per triangle.

use super::compose::DiscBox;
use super::errors::{ErrorTotals, ErrorUnits};
use super::predicates::{self, GridPoint, Lattice};
use super::raster::Grid;
use super::triangle_memo::TriangleMemo;
use super::triangulation::{NONE, Triangulation, copy_fitted, next, prev};
use super::{EvaluateError, Score};
use crate::baselines::hole;
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// A kept set's canonical triangulation with the error of every grid point: what
/// [`Evaluator::score_into`](super::Evaluator::score_into) makes and
/// [`Evaluator::edit`](super::Evaluator::edit) changes. Cloning one is a plain copy (use
/// `clone_from` to reuse the buffers).
#[derive(Debug, Default)]
pub struct MeshState {
    /// The height field it was scored on (`None` until scored).
    pub(super) hf: Option<Arc<Heightfield>>,
    pub(super) kept: Vec<bool>,
    pub(super) mesh: Triangulation,
    /// Per triangle slot, the error totals of the grid points it owns (its vertices excluded).
    pub(super) totals: Vec<ErrorTotals>,
    /// Per kept grid point, a triangle slot of its star: exact after every build, edit or
    /// composition (walks and star walks start there). Unspecified for other points.
    pub(super) hint: Vec<u32>,
    pub(super) score: Option<Score>,
    /// Per triangle slot, the grid box of its circumcircle's disc (see
    /// [`compose`](super::compose)); valid only while `discs_valid`. Filled on demand, not by
    /// builds and edits, which would pay for it on every triangle.
    pub(super) discs: Vec<super::compose::DiscBox>,
    pub(super) discs_valid: bool,
    /// The kept points as a bitset (bit `i` of word `i / 64`) and as a summed-area table
    /// (`(W + 1) × (H + 1)`, kept points in columns < x of rows < y at (y, x)); valid only while
    /// `lookup_valid`. Filled on demand with the disc boxes, for the crossovers this mesh is a
    /// parent of.
    pub(super) kept_bits: Vec<u64>,
    pub(super) kept_sat: Vec<u32>,
    pub(super) lookup_valid: bool,
    /// Changes whenever the mesh does (a new number from [`next_revision`] at every scoring),
    /// so that what was derived from one mesh ([`PartClasses`](super::compose::PartClasses))
    /// can tell it from later ones; 0 until scored. A copy keeps it: it is the same mesh.
    pub(super) revision: u64,
}

/// A number no mesh state had before (in this process).
pub(super) fn next_revision() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

impl Clone for MeshState {
    fn clone(&self) -> Self {
        let mut copy = Self::default();
        copy.clone_from(self);
        copy
    }

    /// Field by field, reusing this state's buffers (the derived one would reallocate).
    fn clone_from(&mut self, source: &Self) {
        self.hf.clone_from(&source.hf);
        self.kept.clone_from(&source.kept);
        self.mesh.clone_from(&source.mesh);
        copy_fitted(&mut self.totals, &source.totals);
        self.hint.clone_from(&source.hint);
        self.score = source.score;
        self.revision = source.revision;
        // A copy is about to be edited (that is what the scorer copies for): the disc boxes,
        // which an edit keeps up to date slot by slot, are copied (cheaper than making them
        // again); the kept points' lookups, which it does not, are not.
        self.discs_valid = source.discs_valid;
        if source.discs_valid {
            copy_fitted(&mut self.discs, &source.discs);
        }
        self.lookup_valid = false;
    }
}

/// Scratch buffers of an edit, kept by the evaluator between calls.
#[derive(Clone, Debug, Default)]
pub(super) struct EditScratch {
    stack: Vec<u32>,
    /// Slots written by this edit (repeats allowed).
    touched: Vec<u32>,
    /// Slots emptied by removals, to be filled by compaction.
    dead: Vec<u32>,
    dirty: Vec<bool>,
    /// The dirty slots, increasing.
    dirty_slots: Vec<u32>,
    boundary: Vec<u32>,
    outer: Vec<u32>,
    star: Vec<u32>,
    fill: Vec<[u32; 3]>,
    /// Diagonals of a hole's fill seen from one side: (from, to) boundary positions, half-edge.
    diagonals: Vec<(usize, usize, u32)>,
    /// [`MeshState::remove_region`]: per slot, is it in a removed vertex's star?
    in_region: Vec<bool>,
    /// The slots of the region, in the order found.
    region: Vec<u32>,
    /// Per grid point: is it already among `region_points`?
    listed: Vec<bool>,
    /// The kept points of the region's closure, plus the grid corners.
    region_points: Vec<u32>,
    /// Their canonical triangulation.
    sub: Triangulation,
    /// Per grid point, a half-edge of `sub` leaving it.
    leaving: Vec<u32>,
    /// Per half-edge of `sub`: the mesh's half-edge across the region's boundary, or
    /// [`INSIDE`] for an edge that is not on it.
    across: Vec<u32>,
    /// Per triangle of `sub`: its slot in the mesh once taken, or [`NONE`].
    taken: Vec<u32>,
    /// The triangles of `sub` inside the region.
    inside: Vec<u32>,
}

/// [`EditScratch::across`] of a half-edge that is not on the region's boundary.
const INSIDE: u32 = u32::MAX - 1;

/// An edit removes its points region by region (`MeshState::remove_region`) when it removes
/// at least this many.
pub const REGION_MIN_REMOVALS: usize = 16;

/// ... and when the region's remaining kept points number at most this many per removed point.
/// Measured over a paper NSGA-II run on jacksboro_65x65 (20 generations): a region costs
/// ≈0.29 µs per removal (stars, flood, relinking) plus ≈0.43 µs per point triangulated, a
/// one-by-one removal ≈0.69 µs, so a region pays below about one point per removal; the run's
/// regions hold a median 0.66.
pub const REGION_POINTS_PER_REMOVAL: usize = 1;

/// `tri` rotated so that its smallest grid index comes first (orientation kept): the
/// rotation every triangle is rasterised in, so its errors do not depend on how it was made.
#[inline]
pub fn canonical(tri: [u32; 3]) -> [u32; 3] {
    let [a, b, c] = tri;
    if a < b && a < c {
        tri
    } else if b < c {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

/// `tris` as a sorted list of [`canonical`] triples: two triangulations are the same mesh
/// exactly when these lists are equal.
pub fn canonical_set(tris: &[[u32; 3]]) -> Vec<[u32; 3]> {
    // A counting sort by the first index, then each bucket by the other two: a triangle
    // starts at its smallest index, so a bucket holds about two triangles. On the 1.38 M
    // triangles of a paper run's front.json this takes 14 ms where a comparison sort of each
    // list took 30 ms.
    let rotated: Vec<[u32; 3]> = tris.iter().map(|&t| canonical(t)).collect();
    let top = rotated.iter().map(|t| t[0] as usize).max().unwrap_or(0);
    if top > 4 * rotated.len() + 1024 {
        // Few triangles over a large range of indices: the buckets would cost more.
        let mut v = rotated;
        v.sort_unstable();
        return v;
    }
    let mut start = vec![0usize; top + 2];
    for t in &rotated {
        start[t[0] as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut next = start.clone();
    let mut sorted = vec![[0u32; 3]; rotated.len()];
    for t in rotated {
        let at = &mut next[t[0] as usize];
        sorted[*at] = t;
        *at += 1;
    }
    for w in start.windows(2) {
        if w[1] - w[0] > 1 {
            sorted[w[0]..w[1]].sort_unstable();
        }
    }
    sorted
}

impl MeshState {
    /// The score of the state, once scored.
    pub fn score(&self) -> Option<Score> {
        self.score
    }

    /// The triangles (grid-index triples, counter-clockwise), in slot order.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.mesh.triangles()
    }

    /// Is grid point `i` kept? False for indices out of range.
    pub fn is_kept(&self, i: u32) -> bool {
        self.kept.get(i as usize).copied().unwrap_or(false)
    }

    /// Per triangle, in the order of [`triangles`](Self::triangles), Σ |z − z̃| over the grid
    /// points it owns (its vertices excluded), from the totals the state keeps: no
    /// rasterisation. Empty before the state is scored.
    pub fn triangle_error_sums(&self) -> Vec<f64> {
        let Some(hf) = &self.hf else {
            return Vec::new();
        };
        let units = ErrorUnits::of(hf);
        self.totals[..self.mesh.len()]
            .iter()
            .map(|t| units.value(t.sum))
            .collect()
    }

    /// The error |z − z̃| of every grid point (0 at kept points), row-major, rasterised from the
    /// mesh (the state keeps only each triangle's totals).
    pub fn errors(&self) -> Vec<f64> {
        let Some(hf) = &self.hf else {
            return Vec::new();
        };
        let mut errors = vec![0.0; hf.len()];
        let (grid, lattice) = (grid_of(hf), Lattice::new(hf.width()));
        for t in 0..self.mesh.len() {
            let tri = canonical(self.mesh.triangle(t)).map(|i| lattice.point(i));
            grid.for_each_error(tri, |i, d| errors[i] = d);
        }
        errors
    }

    pub(super) fn mesh_mut(&mut self) -> &mut Triangulation {
        &mut self.mesh
    }

    /// Rebuilds from scratch as the canonical triangulation of `kept` (distinct, increasing,
    /// corners included, in range) and scores it.
    pub(super) fn rebuild(&mut self, hf: &Arc<Heightfield>, kept: &[u32]) -> Score {
        self.kept.clear();
        self.kept.resize(hf.len(), false);
        for &i in kept {
            self.kept[i as usize] = true;
        }
        self.mesh.rebuild_delaunay(hf.width(), kept);
        self.rescore_all(hf)
    }

    /// Scores the triangles in `self.mesh` from scratch (they need not be Delaunay; the state
    /// can be edited afterwards only if they are and their twins are linked).
    pub(super) fn rescore_all(&mut self, hf: &Arc<Heightfield>) -> Score {
        if !self.hf.as_ref().is_some_and(|h| Arc::ptr_eq(h, hf)) {
            self.hf = Some(hf.clone());
        }
        // No clearing: every kept point's hint is written below, by one of its triangles.
        self.hint.resize(hf.len(), 0);
        self.totals.clear();
        self.totals.resize(self.mesh.len(), ErrorTotals::default());
        self.rasterise(hf, 0..self.mesh.len() as u32);
        self.finish(hf)
    }

    /// Scores the triangles in `self.mesh` in one pass, without the per-point errors and hints
    /// an edit needs: the same score as [`rescore_all`](Self::rescore_all) (the totals are exact
    /// integers, so the order the triangles are summed in does not matter), with no store per
    /// grid point and no pass over the row totals. The state is left not editable.
    pub(super) fn score_once(&mut self, hf: &Heightfield) -> Score {
        let grid = grid_of(hf);
        let units = ErrorUnits::of(hf);
        let lattice = Lattice::new(hf.width());
        let mesh = &self.mesh;
        let tris = (0..mesh.len()).map(|t| canonical(mesh.triangle(t)).map(|i| lattice.point(i)));
        let all = grid.sum_all(units, tris);
        self.forget();
        self.score_from(units.values(&all), hf.len())
    }

    /// Marks this state as not editable (its mesh is not a linked Delaunay triangulation, or
    /// its per-point errors and hints were not written), and its disc boxes as stale.
    pub(super) fn forget(&mut self) {
        self.hf = None;
        self.revision = 0;
        self.discs_valid = false;
        self.lookup_valid = false;
    }

    /// Scores the state from its triangles' totals, as a new mesh (a new revision, disc boxes
    /// stale).
    pub(super) fn finish(&mut self, hf: &Heightfield) -> Score {
        self.discs_valid = false;
        self.lookup_valid = false;
        self.revision = next_revision();
        let units = ErrorUnits::of(hf);
        let mut all = ErrorTotals::default();
        for t in &self.totals[..self.mesh.len()] {
            all.add(t);
        }
        self.score_from(units.values(&all), hf.len())
    }

    fn score_from(&mut self, (sum, sum_sq, max): (f64, f64, f64), n: usize) -> Score {
        let score = Score {
            e_sum: sum,
            e_max: max,
            rms: (sum_sq / n as f64).sqrt(),
            t: self.mesh.len(),
        };
        self.score = Some(score);
        score
    }

    /// Rasterises the triangles in `slots` (each in its canonical rotation) into their totals,
    /// and points their vertices' hints at them.
    pub(super) fn rasterise(&mut self, hf: &Heightfield, slots: impl Iterator<Item = u32>) {
        let (grid, lattice) = (grid_of(hf), Lattice::new(hf.width()));
        let (mesh, hint, totals) = (&self.mesh, &mut self.hint, &mut self.totals);
        let tris = slots.map(|slot| {
            let tri = canonical(mesh.triangle(slot as usize));
            for v in tri {
                hint[v as usize] = slot;
            }
            (slot, tri.map(|i| lattice.point(i)))
        });
        grid.sum_triangles(ErrorUnits::of(hf), tris, |slot, t| {
            totals[slot as usize] = t
        });
    }

    /// [`rasterise`](Self::rasterise) through `memo` ([`TriangleMemo::sum_triangles`];
    /// `unknown`: scratch).
    pub(super) fn rasterise_with_memo(
        &mut self,
        hf: &Arc<Heightfield>,
        slots: std::ops::Range<u32>,
        memo: &mut TriangleMemo,
        unknown: &mut Vec<(u32, [u32; 3])>,
    ) {
        memo.prepare(Some(hf));
        let (mesh, hint, totals) = (&self.mesh, &mut self.hint, &mut self.totals);
        let tris = slots.map(|slot| {
            let tri = canonical(mesh.triangle(slot as usize));
            for v in tri {
                hint[v as usize] = slot;
            }
            (slot, tri)
        });
        memo.sum_triangles(hf, tris, unknown, |slot, t| totals[slot as usize] = t);
    }

    /// Removes the kept points `remove`, then inserts `insert`, and rescores. On error nothing
    /// changes.
    pub(super) fn edit(
        &mut self,
        hf: &Arc<Heightfield>,
        remove: &[u32],
        insert: &[u32],
        scratch: &mut EditScratch,
    ) -> Result<Score, EvaluateError> {
        if !self.hf.as_ref().is_some_and(|h| Arc::ptr_eq(h, hf)) || self.score.is_none() {
            return Err(EvaluateError::ForeignState);
        }
        self.check_edit(hf, remove, insert)?;
        let discs_valid = self.discs_valid && self.discs.len() == self.mesh.len();
        let lattice = Lattice::new(hf.width());
        scratch.touched.clear();
        scratch.dead.clear();
        if remove.len() < REGION_MIN_REMOVALS || !self.remove_region(hf, lattice, remove, scratch) {
            for &v in remove {
                self.remove_vertex(lattice, v, scratch);
            }
        }
        // The last insertion and a slot next to it: the insertions come in grid order, so it is
        // usually close to the next one.
        let mut last: Option<(u32, u32)> = None;
        for &p in insert {
            let t = self.locate(
                lattice,
                self.insertion_start(lattice, p, last),
                lattice.point(p),
            );
            let touched = &mut scratch.touched;
            let slot = self
                .mesh
                .insert_point(t, p, &mut scratch.stack, |s| touched.push(s));
            last = Some((p, slot));
        }
        self.compact(scratch);
        // Re-rasterise every touched triangle (a new vertex is a vertex of some of them).
        self.totals.resize(self.mesh.len(), ErrorTotals::default());
        let dirty = &scratch.dirty;
        let slots = &mut scratch.dirty_slots;
        slots.clear();
        slots.extend((0..self.mesh.len() as u32).filter(|&s| dirty[s as usize]));
        // Disc boxes that were up to date stay so: the untouched slots hold the same
        // triangles (a composed mesh is a parent-to-be; making all its boxes again cost more
        // than the edit).
        if discs_valid {
            let (w, h) = (hf.width(), hf.height());
            self.discs.truncate(self.mesh.len());
            self.discs.resize(self.mesh.len(), DiscBox::default());
            for &slot in slots.iter() {
                let p = self.mesh.triangle(slot as usize).map(|i| lattice.point(i));
                self.discs[slot as usize] = DiscBox::of(p, w, h);
            }
        }
        self.rasterise(hf, slots.iter().copied());
        let score = self.finish(hf);
        self.discs_valid = discs_valid;
        Ok(score)
    }

    /// Checks (and applies to the kept marks) an edit; on error restores the marks.
    fn check_edit(
        &mut self,
        hf: &Heightfield,
        remove: &[u32],
        insert: &[u32],
    ) -> Result<(), EvaluateError> {
        let n = hf.len();
        let corners = hf.corners();
        let mut problem = None;
        let (mut removed, mut inserted) = (0, 0);
        for &i in remove {
            if i as usize >= n {
                problem = Some(EvaluateError::IndexOutOfRange {
                    index: i as u64,
                    len: n,
                });
            } else if !self.kept[i as usize] || corners.contains(&i) {
                problem = Some(EvaluateError::InvalidEdit {
                    index: i,
                    why: "only a kept point other than a corner can be removed",
                });
            }
            if problem.is_some() {
                break;
            }
            self.kept[i as usize] = false;
            removed += 1;
        }
        if problem.is_none() {
            for &i in insert {
                if i as usize >= n {
                    problem = Some(EvaluateError::IndexOutOfRange {
                        index: i as u64,
                        len: n,
                    });
                } else if self.kept[i as usize] {
                    problem = Some(EvaluateError::InvalidEdit {
                        index: i,
                        why: "the point is kept already",
                    });
                }
                if problem.is_some() {
                    break;
                }
                self.kept[i as usize] = true;
                inserted += 1;
            }
        }
        match problem {
            None => Ok(()),
            Some(e) => {
                for &i in &insert[..inserted] {
                    self.kept[i as usize] = false;
                }
                for &i in &remove[..removed] {
                    self.kept[i as usize] = true;
                }
                Err(e)
            }
        }
    }

    /// Where the walk to insert `p` starts: a triangle of the kept point nearest `p` along its
    /// row (or, when the row keeps none, of a grid corner), unless the last insertion `last`
    /// (point, slot) is nearer. A hint may have gone stale during this edit (its slot split or
    /// emptied since): the walk starts anywhere.
    fn insertion_start(&self, lattice: Lattice, p: u32, last: Option<(u32, u32)>) -> u32 {
        let pp = lattice.point(p);
        let width = lattice.width();
        let row = (pp[1] as usize) * width;
        let near = (1..width as i64).find_map(|d| {
            [pp[0] - d, pp[0] + d]
                .into_iter()
                .filter(|&x| (0..width as i64).contains(&x))
                .map(|x| (row + x as usize) as u32)
                .find(|&q| self.kept[q as usize])
        });
        // Grid corner 0 is always kept.
        let (kept, dist) = near.map_or((0, i64::MAX), |q| (q, (lattice.point(q)[0] - pp[0]).abs()));
        if let Some((q, slot)) = last {
            let a = lattice.point(q);
            if (a[0] - pp[0]).abs() + (a[1] - pp[1]).abs() < dist {
                return slot;
            }
        }
        self.hint[kept as usize]
    }

    /// The live triangle whose closed area holds `p`, by a visibility walk from slot `start`
    /// (any slot: a dead one forwards to a live one nearby, an out-of-range one starts from the
    /// first live triangle), with an exhaustive search behind the walk's step cap.
    pub(super) fn locate(&self, lattice: Lattice, start: u32, p: GridPoint) -> u32 {
        let m = &self.mesh;
        let live = |t: u32| (t as usize) < m.len() && m.vertices[3 * t as usize] != NONE;
        let mut t = start;
        // A dead slot forwards to a live triangle of its hole (which may have died since).
        for _ in 0..8 {
            if (t as usize) < m.len() && !live(t) {
                t = m.twin[3 * t as usize];
            }
        }
        if !live(t) {
            t = (0..m.len() as u32)
                .find(|&t| live(t))
                .expect("a mesh has a triangle");
        }
        if let Some(t) = m.walk(t, p, m.walk_cap()) {
            return t;
        }
        let point = |i: u32| lattice.point(i);
        (0..m.len() as u32)
            .filter(|&t| live(t))
            .find(|&t| {
                let [a, b, c] = m.triangle(t as usize).map(point);
                [(a, b), (b, c), (c, a)]
                    .iter()
                    .all(|&(u, v)| predicates::orient(u, v, p) >= 0)
            })
            .expect("the grid rectangle is covered by the triangles")
    }

    /// Removes the kept vertices `remove` (not corners) all at once: the union of their stars
    /// (the region) is the only part of the mesh that changes, since a removal never makes
    /// another triangle's circle non-empty. The new triangles there are those of the canonical
    /// triangulation of the region's remaining kept points (plus the grid corners, so that it can
    /// be built by insertion) that lie inside the region: every triangle of the edited mesh
    /// inside the region has an empty circle among all kept points, so among these too. They are
    /// found by a flood from the region's boundary edges. Returns false, changing nothing, when
    /// the region holds too many points for this to pay ([`REGION_POINTS_PER_REMOVAL`]).
    ///
    /// Why: an OAX child takes whole blocks from the other parent, so its removals are dense in
    /// a few blocks, where re-triangulating the block's survivors costs about a third of
    /// removing its points one hole at a time.
    fn remove_region(
        &mut self,
        hf: &Heightfield,
        lattice: Lattice,
        remove: &[u32],
        scratch: &mut EditScratch,
    ) -> bool {
        let m = &self.mesh;
        let n = hf.len();
        scratch.in_region.clear();
        scratch.in_region.resize(m.len(), false);
        scratch.region.clear();
        // The stars, by rotating around each removed vertex from a triangle that has it.
        for &v in remove {
            let t = self.locate(lattice, self.hint[v as usize], lattice.point(v));
            let Some(e) = m.leaving(t, v) else {
                return false;
            };
            for e in m.fan(e) {
                let slot = (e / 3) as usize;
                if !scratch.in_region[slot] {
                    scratch.in_region[slot] = true;
                    scratch.region.push(slot as u32);
                }
            }
        }
        // The region's remaining kept points (`kept` already says which are removed), and the
        // corners.
        // (The marks are cleared again right after, so the buffer is only ever resized.)
        scratch.listed.resize(n, false);
        scratch.region_points.clear();
        scratch.region_points.extend(hf.corners());
        for &c in &scratch.region_points {
            scratch.listed[c as usize] = true;
        }
        let limit = REGION_POINTS_PER_REMOVAL * remove.len() + 4;
        for &slot in &scratch.region {
            for k in 0..3 {
                let v = m.vertices[3 * slot as usize + k];
                if self.kept[v as usize] && !scratch.listed[v as usize] {
                    scratch.listed[v as usize] = true;
                    scratch.region_points.push(v);
                }
            }
            if scratch.region_points.len() > limit {
                break;
            }
        }
        for &v in &scratch.region_points {
            scratch.listed[v as usize] = false;
        }
        if scratch.region_points.len() > limit {
            return false;
        }
        scratch.region_points.sort_unstable();
        let sub = &mut scratch.sub;
        if !sub.insert_all(hf.width(), &scratch.region_points) {
            return false;
        }
        // Where each of sub's points has a half-edge leaving it.
        scratch.leaving.resize(n, NONE);
        for (e, &v) in sub.vertices.iter().enumerate() {
            scratch.leaving[v as usize] = e as u32;
        }
        // The region's boundary edges that face a triangle outside it: each is an edge of sub
        // with the region on its left, the same direction as in the mesh.
        scratch.across.clear();
        scratch.across.resize(sub.vertices.len(), INSIDE);
        scratch.taken.clear();
        scratch.taken.resize(sub.len(), NONE);
        scratch.inside.clear();
        for &slot in &scratch.region {
            for h in 3 * slot..3 * slot + 3 {
                let outer = m.twin[h as usize];
                if outer == NONE || scratch.in_region[(outer / 3) as usize] {
                    continue;
                }
                let (u, v) = (m.vertices[h as usize], m.vertices[next(h) as usize]);
                let Some(e) = edge_from(sub, scratch.leaving[u as usize], v) else {
                    return false;
                };
                scratch.across[e as usize] = outer;
                let t = e / 3;
                if scratch.taken[t as usize] == NONE {
                    scratch.taken[t as usize] = 0;
                    scratch.inside.push(t);
                }
            }
        }
        if scratch.inside.is_empty() {
            // The region is the whole mesh: every triangle of sub is inside.
            if scratch.region.len() != m.len() {
                return false;
            }
            scratch.inside.extend(0..sub.len() as u32);
        } else {
            // Flood from the triangles on the boundary, never across it.
            let (across, taken) = (&scratch.across, &mut scratch.taken);
            sub.flood(
                &mut scratch.inside,
                |e| across[e as usize] != INSIDE,
                |t| std::mem::replace(&mut taken[t as usize], 0) == NONE,
            );
        }
        // A guard on the reasoning above: the new triangles cover exactly the region's area.
        let area = |v: &[u32]| -> i64 {
            let [a, b, c] = [v[0], v[1], v[2]].map(|i| lattice.point(i));
            predicates::orient(a, b, c)
        };
        let old_area: i64 = scratch
            .region
            .iter()
            .map(|&t| area(&m.vertices[3 * t as usize..]))
            .sum();
        let new_area: i64 = scratch
            .inside
            .iter()
            .map(|&t| area(&sub.vertices[3 * t as usize..]))
            .sum();
        if old_area != new_area {
            debug_assert!(
                false,
                "a region's new triangles cover {new_area}, not {old_area}"
            );
            return false;
        }
        // Nothing has changed so far; from here the mesh is rewritten. The region's slots take
        // the new triangles, further ones are appended, left-over slots die.
        let m = &mut self.mesh;
        let mut slots = scratch.region.iter().copied();
        for &t in &scratch.inside {
            let slot = match slots.next() {
                Some(slot) => slot,
                None => {
                    m.vertices.extend_from_slice(&[NONE; 3]);
                    m.twin.extend_from_slice(&[NONE; 3]);
                    (m.len() - 1) as u32
                }
            };
            scratch.taken[t as usize] = slot;
            let base = 3 * slot as usize;
            m.vertices[base..base + 3]
                .copy_from_slice(&sub.vertices[3 * t as usize..3 * t as usize + 3]);
            scratch.touched.push(slot);
        }
        let live = scratch.taken[scratch.inside[0] as usize];
        for slot in slots {
            let base = 3 * slot as usize;
            m.vertices[base..base + 3].fill(NONE);
            m.twin[base..base + 3].fill(NONE);
            // Forwards a walk that starts here to a live triangle of the region.
            m.twin[base] = live;
            scratch.dead.push(slot);
        }
        for &t in &scratch.inside {
            let slot = scratch.taken[t as usize];
            for k in 0..3 {
                let e = 3 * t + k;
                let h = 3 * slot + k;
                let outer = scratch.across[e as usize];
                let twin = if outer != INSIDE {
                    outer
                } else {
                    let f = sub.twin[e as usize];
                    if f == NONE {
                        NONE
                    } else {
                        3 * scratch.taken[(f / 3) as usize] + f % 3
                    }
                };
                m.twin[h as usize] = twin;
                if twin != NONE {
                    m.twin[twin as usize] = h;
                }
            }
        }
        true
    }

    /// Removes kept vertex `v` (not a corner): deletes its star and fills the hole with the
    /// Delaunay triangles of its boundary, in the star's slots; emptied slots go to
    /// `scratch.dead`.
    fn remove_vertex(&mut self, lattice: Lattice, v: u32, scratch: &mut EditScratch) {
        let t = self.locate(lattice, self.hint[v as usize], lattice.point(v));
        let m = &mut self.mesh;
        let leaving = m
            .leaving(t, v)
            .expect("a kept point is a vertex of the triangle that holds it");
        // Half-edges v → a leave v; from the first triangle of the fan (a border vertex's fan is
        // open)...
        let mut e = m.fan_start(leaving);
        // Then counter-clockwise: triangle (v, aᵢ, aᵢ₊₁) gives the boundary edge aᵢ → aᵢ₊₁.
        let start = e;
        scratch.star.clear();
        scratch.boundary.clear();
        scratch.outer.clear();
        loop {
            scratch.star.push(e / 3);
            let link = next(e);
            scratch.boundary.push(m.vertices[link as usize]);
            scratch.outer.push(m.twin[link as usize]);
            let back = m.fan_next(e);
            if back == NONE {
                // A border vertex: the chain ends at aₖ, closed by a border segment.
                scratch.boundary.push(m.vertices[prev(e) as usize]);
                break;
            }
            e = back;
            if e == start {
                break;
            }
        }
        scratch.fill.clear();
        let filled = hole::fill(&scratch.boundary, lattice, &mut scratch.fill);
        assert!(filled, "the star of a Delaunay vertex has a Delaunay fill");
        let links = scratch.outer.len();
        let b = &scratch.boundary;
        for (j, &slot) in scratch.star.iter().enumerate() {
            let base = 3 * slot as usize;
            match scratch.fill.get(j) {
                Some(tri) => {
                    m.vertices[base..base + 3].copy_from_slice(tri);
                    scratch.touched.push(slot);
                }
                None => {
                    // Dead until compaction; its first twin forwards a walk that starts here to
                    // a live triangle of the same hole.
                    m.vertices[base..base + 3].fill(NONE);
                    m.twin[base..base + 3].fill(NONE);
                    m.twin[base] = scratch.star[0];
                    scratch.dead.push(slot);
                }
            }
        }
        // Link the new triangles: a boundary edge bᵢ → bᵢ₊₁ to the outer side of the hole (or
        // to nothing: the border segment that closes a border vertex's chain), a diagonal to
        // its reverse in another new triangle.
        let slots = &scratch.star[..scratch.fill.len()];
        let diagonals = &mut scratch.diagonals;
        diagonals.clear();
        for (j, &slot) in slots.iter().enumerate() {
            let at = scratch.fill[j].map(|v| {
                b.iter()
                    .position(|&x| x == v)
                    .expect("the fill's vertices are the boundary's")
            });
            for kk in 0..3 {
                let h = 3 * slot + kk as u32;
                let (from, to) = (at[kk], at[(kk + 1) % 3]);
                let successor = if from + 1 == b.len() { 0 } else { from + 1 };
                let twin = if to == successor {
                    if from < links {
                        scratch.outer[from]
                    } else {
                        NONE
                    }
                } else if let Some(q) = diagonals.iter().position(|d| (d.0, d.1) == (to, from)) {
                    diagonals.swap_remove(q).2
                } else {
                    diagonals.push((from, to, h));
                    continue;
                };
                m.twin[h as usize] = twin;
                if twin != NONE {
                    m.twin[twin as usize] = h;
                }
            }
        }
        debug_assert!(diagonals.is_empty(), "every diagonal has two sides");
    }

    /// Moves the last live triangles into the slots removals emptied, so slots are `0..T`
    /// again, and sets `scratch.dirty` for every slot whose triangle must be rasterised again
    /// (written or moved by this edit).
    fn compact(&mut self, scratch: &mut EditScratch) {
        let m = &mut self.mesh;
        let dirty = &mut scratch.dirty;
        dirty.clear();
        dirty.resize(m.len(), false);
        for &s in &scratch.touched {
            dirty[s as usize] = true;
        }
        scratch.dead.sort_unstable();
        let mut len = m.len();
        for &d in &scratch.dead {
            while len > 0 && m.vertices[3 * (len - 1)] == NONE {
                len -= 1;
            }
            if d as usize >= len {
                break;
            }
            let from = len - 1;
            for k in 0..3 {
                let (src, dst) = (3 * from + k, 3 * d as usize + k);
                m.vertices[dst] = m.vertices[src];
                let tw = m.twin[src];
                m.twin[dst] = tw;
                if tw != NONE {
                    m.twin[tw as usize] = dst as u32;
                }
            }
            // A moved triangle keeps its errors but its points' hints name the old slot.
            dirty[d as usize] = true;
            len -= 1;
        }
        m.vertices.truncate(3 * len);
        m.twin.truncate(3 * len);
    }
}

/// The half-edge of `mesh` from the origin of its half-edge `leaving` to `to`, by walking that
/// origin's fan from `leaving`: counter-clockwise, then, past the border, clockwise. (Not from
/// the fan's first half-edge, which for an inner vertex means walking the whole fan first: the
/// walk is a chain of dependent reads, a third of a crossover's preparation.)
pub(super) fn edge_from(mesh: &Triangulation, leaving: u32, to: u32) -> Option<u32> {
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

pub(super) fn grid_of(hf: &Heightfield) -> Grid<'_> {
    Grid {
        width: hf.width() as i64,
        height: hf.height() as i64,
        z: hf.z(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::Evaluator;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn canonical_rotation_starts_at_the_smallest_index_and_keeps_orientation() {
        // The three rotations of one counter-clockwise triangle map to the same triple.
        for tri in [[3, 9, 5], [9, 5, 3], [5, 3, 9]] {
            assert_eq!(canonical(tri), [3, 9, 5]);
        }
    }

    #[test]
    fn the_canonical_set_is_the_sorted_list_of_rotations() {
        // Random lists, with repeated first indices (buckets of several triangles), repeated
        // triangles, and indices spread far beyond the list's length (the comparison-sort path):
        // the result must equal the plain sort of the canonical rotations.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(4);
        for (len, range) in [(0, 10), (1, 5), (50, 20), (400, 300), (30, 1_000_000)] {
            let tris: Vec<[u32; 3]> = (0..len)
                .map(|_| {
                    let a = rng.random_range(0..range);
                    let t = [
                        a,
                        a + 1 + rng.random_range(0..9),
                        a + 10 + rng.random_range(0..9),
                    ];
                    let r = rng.random_range(0..3);
                    [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
                })
                .collect();
            let mut expected: Vec<[u32; 3]> = tris.iter().map(|&t| canonical(t)).collect();
            expected.sort_unstable();
            assert_eq!(canonical_set(&tris), expected, "{len} over {range}");
        }
    }

    /// An edit keeps up-to-date disc boxes up to date (and a copy takes them along): after
    /// removals (small ones and regions, which compact the slots) and insertions, on copies
    /// too, every box is the one made afresh for its slot's triangle.
    #[test]
    fn edits_keep_the_disc_boxes_of_every_slot() {
        let (w, h) = (33usize, 29usize);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let z = (0..w * h).map(|_| rng.random::<f64>() * 10.0).collect();
        let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
        let kept: Vec<u32> = (0..(w * h) as u32)
            .filter(|_| rng.random::<f64>() < 0.3)
            .collect();
        let mut ev = Evaluator::new(hf.clone());
        let mut state = MeshState::default();
        ev.score_into(&kept, &mut state).unwrap();
        state.ensure_discs();
        let corners = hf.corners();
        let lattice = Lattice::new(w);
        for round in 0..40 {
            let mut copy = MeshState::default();
            copy.clone_from(&state);
            let removals = [1, 3, 30][round % 3];
            let remove: Vec<u32> = (0..(w * h) as u32)
                .filter(|&i| copy.is_kept(i) && !corners.contains(&i))
                .filter(|_| rng.random_range(0..200) < removals)
                .collect();
            let insert: Vec<u32> = (0..(w * h) as u32)
                .filter(|&i| !copy.is_kept(i) && rng.random_range(0..300) == 0)
                .collect();
            ev.edit(&mut copy, &remove, &insert).unwrap();
            assert!(copy.discs_valid, "round {round}");
            assert_eq!(copy.discs.len(), copy.mesh.len(), "round {round}");
            for t in 0..copy.mesh.len() {
                let p = copy.mesh.triangle(t).map(|i| lattice.point(i));
                assert_eq!(
                    copy.discs[t],
                    DiscBox::of(p, w, h),
                    "round {round}, slot {t}"
                );
            }
            state = copy;
        }
    }

    #[test]
    fn a_block_removed_as_a_region_matches_a_fresh_build() {
        // A 30×24 grid of uneven heights, 40 % kept; every kept point of a block (one border
        // side included, so border edges merge) goes: the edit takes the region path, and its
        // mesh and score are the fresh build's.
        let (w, h) = (30usize, 24usize);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let z = (0..w * h).map(|_| rng.random::<f64>() * 10.0).collect();
        let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
        let kept: Vec<u32> = (0..(w * h) as u32)
            .filter(|_| rng.random::<f64>() < 0.4)
            .collect();
        let mut ev = Evaluator::new(hf.clone());
        let mut state = MeshState::default();
        ev.score_into(&kept, &mut state).unwrap();
        let corners = hf.corners();
        let remove: Vec<u32> = (0..h)
            .flat_map(|y| (0..12).map(move |x| (y * w + x) as u32))
            .filter(|&i| state.is_kept(i) && !corners.contains(&i) && (i as usize / w) % 5 != 2)
            .collect();
        assert!(remove.len() >= REGION_MIN_REMOVALS);
        // The same removal on a copy, by the region path alone.
        let mut copy = state.clone();
        for &v in &remove {
            copy.kept[v as usize] = false;
        }
        let mut scratch = EditScratch::default();
        let lattice = Lattice::new(w);
        assert!(copy.remove_region(&hf, lattice, &remove, &mut scratch));

        let score = ev.edit(&mut state, &remove, &[]).unwrap();
        let left: Vec<u32> = kept
            .iter()
            .copied()
            .filter(|i| !remove.contains(i))
            .collect();
        let fresh = ev.evaluate(&left).unwrap();
        assert_eq!(score.e_sum.to_bits(), fresh.score.e_sum.to_bits());
        assert_eq!(score.t, fresh.score.t);
        assert_eq!(
            canonical_set(&state.triangles()),
            canonical_set(&fresh.triangles)
        );
    }
}
