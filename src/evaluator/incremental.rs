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
//!   triangle gives the same bits whichever way it was created. A triangle that no edit touched
//!   owns the same points with the same errors as before; only the touched triangles are
//!   rasterised again.
//! - The totals are summed in the grid's fixed order ([`ErrorField`]): only rows that contain a
//!   re-rasterised point are re-added.
//!
//! Cost: an edit costs about its walk, its flips or hole fill, and the area of the triangles it
//! changed; a state costs ≈ 13 bytes per grid point plus 24 bytes per triangle.

use super::errors::ErrorField;
use super::predicates::{self, GridPoint, Lattice};
use super::raster::Grid;
use super::triangulation::{NONE, Triangulation, next, prev};
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
    hf: Option<Arc<Heightfield>>,
    kept: Vec<bool>,
    mesh: Triangulation,
    field: ErrorField,
    /// Per grid point, a triangle slot: the triangle that owns it, or for a kept point one of
    /// its triangles. Exact after every build or edit; a walk starts there.
    hint: Vec<u32>,
    score: Option<Score>,
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
        self.field.clone_from(&source.field);
        self.hint.clone_from(&source.hint);
        self.score = source.score;
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
    dirty_rows: Vec<bool>,
    boundary: Vec<u32>,
    outer: Vec<u32>,
    star: Vec<u32>,
    fill: Vec<[u32; 3]>,
    /// Diagonals of a hole's fill seen from one side: (from, to) boundary positions, half-edge.
    diagonals: Vec<(usize, usize, u32)>,
}

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
    let mut v: Vec<[u32; 3]> = tris.iter().map(|&t| canonical(t)).collect();
    v.sort_unstable();
    v
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

    /// The error |z − z̃| of every grid point (0 at kept points), row-major.
    pub fn errors(&self) -> &[f64] {
        self.field.errors()
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
        // No clearing: every point's error and hint is written below, by the triangle that owns
        // it or, for a vertex, by one of its triangles.
        self.field.reshape(hf.width(), hf.height());
        self.hint.resize(hf.len(), 0);
        let grid = grid_of(hf);
        let lattice = Lattice::new(hf.width());
        for slot in 0..self.mesh.len() as u32 {
            self.rasterise(&grid, lattice, slot);
        }
        self.field.refresh_all();
        self.finish(hf.len())
    }

    /// Marks this state as not editable (its mesh is not a linked Delaunay triangulation).
    pub(super) fn forget(&mut self) {
        self.hf = None;
    }

    fn finish(&mut self, n: usize) -> Score {
        let (sum, sum_sq, max) = self.field.totals();
        let score = Score {
            e_sum: sum,
            e_max: max,
            rms: (sum_sq / n as f64).sqrt(),
            t: self.mesh.len(),
        };
        self.score = Some(score);
        score
    }

    /// Writes the errors of the points triangle `slot` owns, and points its points' and
    /// vertices' hints at it. Returns its lowest and highest row.
    #[inline]
    fn rasterise(&mut self, grid: &Grid<'_>, lattice: Lattice, slot: u32) -> (usize, usize) {
        let tri = canonical(self.mesh.triangle(slot as usize));
        let pts = tri.map(|i| lattice.point(i));
        let (field, hint) = (&mut self.field, &mut self.hint);
        grid.write_errors(pts, field.errors_mut(), |first, last| {
            hint[first..=last].fill(slot);
        });
        for v in tri {
            // A vertex is a kept point: its error is zero by definition.
            field.set(v as usize, 0.0);
            hint[v as usize] = slot;
        }
        let ys = pts.map(|p| p[1] as usize);
        (ys[0].min(ys[1]).min(ys[2]), ys[0].max(ys[1]).max(ys[2]))
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
        let lattice = Lattice::new(hf.width());
        scratch.touched.clear();
        scratch.dead.clear();
        for &v in remove {
            self.remove_vertex(lattice, v, scratch);
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
        // Re-rasterise every touched triangle and re-add the rows they cover.
        let grid = grid_of(hf);
        let rows = &mut scratch.dirty_rows;
        rows.clear();
        rows.resize(hf.height(), false);
        for slot in 0..self.mesh.len() {
            if scratch.dirty[slot] {
                let (lo, hi) = self.rasterise(&grid, lattice, slot as u32);
                rows[lo..=hi].fill(true);
            }
        }
        // A new vertex is a vertex of the touched triangles just rasterised, which set its error
        // to zero and marked its row.
        self.field
            .refresh_rows(rows.iter().enumerate().filter(|(_, d)| **d).map(|(y, _)| y));
        Ok(self.finish(hf.len()))
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

    /// Where the walk to insert `p` starts: its hint (the triangle that owned it before this
    /// edit), unless the last insertion `last` (point, slot) is nearer. The hint's triangle
    /// may have been split many times by this edit's insertions and now hold a far piece.
    fn insertion_start(&self, lattice: Lattice, p: u32, last: Option<(u32, u32)>) -> u32 {
        let hint = self.hint[p as usize];
        let Some((q, slot)) = last else {
            return hint;
        };
        let pp = lattice.point(p);
        let dist = |v: u32| {
            let a = lattice.point(v);
            (a[0] - pp[0]).pow(2) + (a[1] - pp[1]).pow(2)
        };
        let m = &self.mesh;
        let hint_dist = if (hint as usize) < m.len() && m.vertices[3 * hint as usize] != NONE {
            m.triangle(hint as usize)
                .map(dist)
                .into_iter()
                .min()
                .unwrap_or(i64::MAX)
        } else {
            i64::MAX
        };
        if dist(q) < hint_dist { slot } else { hint }
    }

    /// The live triangle whose closed area holds `p`, by a visibility walk from slot `start`
    /// (any slot: a dead one forwards to a live one nearby, an out-of-range one starts from the
    /// first live triangle), with an exhaustive search behind the walk's step cap.
    fn locate(&self, lattice: Lattice, start: u32, p: GridPoint) -> u32 {
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

    /// Removes kept vertex `v` (not a corner): deletes its star and fills the hole with the
    /// Delaunay triangles of its boundary, in the star's slots; emptied slots go to
    /// `scratch.dead`.
    fn remove_vertex(&mut self, lattice: Lattice, v: u32, scratch: &mut EditScratch) {
        let t = self.locate(lattice, self.hint[v as usize], lattice.point(v));
        let m = &mut self.mesh;
        let k = (0..3)
            .find(|&k| m.vertices[3 * t as usize + k] == v)
            .expect("a kept point is a vertex of the triangle that holds it");
        // Half-edges v → a leave v; rotate clockwise to the first triangle of the fan (a border
        // vertex's fan is open) or once around.
        let first = 3 * t + k as u32;
        let mut e = first;
        loop {
            let f = m.twin[e as usize];
            if f == NONE {
                break;
            }
            e = next(f);
            if e == first {
                break;
            }
        }
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
            let back = m.twin[prev(e) as usize];
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

fn grid_of(hf: &Heightfield) -> Grid<'_> {
    Grid {
        width: hf.width() as i64,
        height: hf.height() as i64,
        z: hf.z(),
    }
}

#[cfg(test)]
mod tests {
    use super::canonical;

    #[test]
    fn canonical_rotation_starts_at_the_smallest_index_and_keeps_orientation() {
        // The three rotations of one counter-clockwise triangle map to the same triple.
        for tri in [[3, 9, 5], [9, 5, 3], [5, 3, 9]] {
            assert_eq!(canonical(tri), [3, 9, 5]);
        }
    }
}
