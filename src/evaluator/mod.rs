//! The evaluator, ruler of the whole project: the Delaunay triangulation of a kept set of grid
//! points, and the error E = Σ over all N grid points of |z − z̃| (the source paper's eq. 2–4).
//!
//! Contract:
//! - The four grid corners are always kept, whether or not the caller lists them; duplicates are
//!   ignored.
//! - The triangulation is the canonical Delaunay triangulation of the kept points (one per point
//!   set; ties settled by the tie rule in `exact/predicates.rs`).
//! - Every grid point is counted exactly once: kept points contribute 0; every other point is
//!   interpolated linearly on the one triangle that owns it (see `raster/`).
//! - `rms = sqrt(Σ (z − z̃)² / N)` over all N grid points.
//! - The sums are exact integers in fixed point: each error counts as a whole number of units of
//!   one power of two, chosen per height field (under 10⁻¹⁴ of the z range on a 65×65 grid; see
//!   `exact/fixed_point.rs`), so they are the same in any order; and each triangle is rasterised
//!   in one fixed rotation. So the numbers of a kept set are the same bits however its mesh was
//!   made.
//!
//! Besides scoring a kept set from scratch, the evaluator can keep the scored mesh in a
//! [`MeshState`] and score a nearby kept set by editing it ([`Evaluator::edit`]: local removals
//! and insertions, only the changed triangles rasterised again), with bit-identical results.
//!
//! Layers, each using only those below it:
//! - `score.rs` and `error.rs`: the numbers of a mesh and why a request fails, which every layer
//!   speaks;
//! - `exact/`: integer predicates and the tie rule, fixed-point error sums, and the paper's E by
//!   brute force (`paper_e.rs`, the reference the tests hold every path to);
//! - `mesh/`: the canonical Delaunay triangulation (`canonical_triangulation/`: the mesh, its
//!   insertion on packed half-edges, its insertion order), canonical forms, [`MeshState`], hole
//!   fill and region wrapping;
//! - `raster/`: which triangle owns which grid point, span sums, the fresh build of a mesh;
//! - `edit/` (remove and insert points) and `compose/` (the OAX composition of two parents);
//! - `part_scores/`: a crossover's children and mutants scored without their meshes;
//! - this facade, [`Evaluator`].
//!
//! ```
//! use paretomesh::{evaluator::Evaluator, heightfield::Heightfield};
//! // A 3×3 grid, flat but for a bump of 4 in the middle.
//! let mut z = vec![0.0; 9];
//! z[4] = 4.0;
//! let hf = Heightfield::new(3, 3, z).unwrap();
//! let mut ev = Evaluator::new(std::sync::Arc::new(hf));
//! let corners_only = ev.evaluate(&[]).unwrap();
//! assert_eq!((corners_only.score.e_sum, corners_only.score.t), (4.0, 2));
//! let with_bump = ev.evaluate(&[4]).unwrap();
//! assert_eq!((with_bump.score.e_sum, with_bump.score.t), (0.0, 4));
//! ```

pub(crate) mod compose;
pub(crate) mod edit;
pub(crate) mod error;
pub(crate) mod exact;
pub(crate) mod mesh;
pub(crate) mod part_scores;
pub(crate) mod raster;
pub(crate) mod score;
#[cfg(test)]
pub(crate) mod test_grids;
#[cfg(test)]
mod tests;

pub use compose::{Crossing, PartClasses};
pub use error::{EvaluateError, check_indices};
pub use mesh::canonical_form::canonical_set;
pub use mesh::canonical_triangulation::Triangulation;
pub(crate) use mesh::delaunay_check::is_delaunay;
pub use mesh::state::{GridLookups, MeshState};
pub(crate) use part_scores::Changes;
pub use part_scores::PartScores;
pub use score::{Evaluation, Score};

use crate::heightfield::Heightfield;
use edit::EditScratch;
use exact::predicates;
use raster::Grid;
use std::sync::Arc;

/// Scores kept sets (or whole triangulations) on one height field. Reuses its buffers between
/// calls, so keep one per thread.
pub struct Evaluator {
    hf: Arc<Heightfield>,
    kept_mark: Vec<bool>,
    kept: Vec<u32>,
    /// The last mesh scored by [`score`](Self::score) or
    /// [`score_triangulation`](Self::score_triangulation).
    state: MeshState,
    scratch: EditScratch,
    compose_scratch: compose::ComposeScratch,
    row_scratch: part_scores::RowScratch,
}

impl Evaluator {
    /// An evaluator for `hf`.
    pub fn new(hf: Arc<Heightfield>) -> Self {
        Self {
            kept_mark: vec![false; hf.len()],
            hf,
            kept: Vec::new(),
            state: MeshState::default(),
            scratch: EditScratch::default(),
            compose_scratch: compose::ComposeScratch::default(),
            row_scratch: part_scores::RowScratch::default(),
        }
    }

    /// The height field this evaluator scores on.
    pub(crate) fn heightfield(&self) -> &Arc<Heightfield> {
        &self.hf
    }

    /// Triangulates `kept` (plus the corners) and scores it, with the triangles.
    pub fn evaluate(&mut self, kept: &[u32]) -> Result<Evaluation, EvaluateError> {
        let score = self.score(kept)?;
        Ok(Evaluation {
            score,
            triangles: self.state.triangles(),
        })
    }

    /// Triangulates `kept` (plus the corners) and scores it, in one pass over the triangles
    /// that keeps no per-point error (see [`score_into`](Self::score_into) for a mesh that can
    /// be edited; both give the same score).
    pub fn score(&mut self, kept: &[u32]) -> Result<Score, EvaluateError> {
        self.gather(kept)?;
        self.state
            .mesh_mut()
            .rebuild_delaunay(self.hf.width(), &self.kept);
        Ok(self.state.score_once(&self.hf))
    }

    /// Like [`score`](Self::score), but builds the mesh into `state`, which can then be edited
    /// ([`edit`](Self::edit)) to score nearby kept sets.
    pub fn score_into(
        &mut self,
        kept: &[u32],
        state: &mut MeshState,
    ) -> Result<Score, EvaluateError> {
        self.gather(kept)?;
        Ok(state.rebuild(&self.hf, &self.kept))
    }

    /// Checks `kept` and sets `self.kept` to it plus the corners, increasing, without repeats.
    fn gather(&mut self, kept: &[u32]) -> Result<(), EvaluateError> {
        check_indices(kept, self.hf.len())?;
        for &i in kept.iter().chain(self.hf.corners().iter()) {
            self.kept_mark[i as usize] = true;
        }
        // Collect unique indices and clear the marks in the same pass. Callers usually pass
        // increasing indices: then merging in the (increasing) corners keeps the list sorted.
        self.kept.clear();
        let corners = self.hf.corners();
        let mut next_corner = 0;
        let take = |i: u32, marks: &mut [bool], out: &mut Vec<u32>| {
            if std::mem::replace(&mut marks[i as usize], false) {
                out.push(i);
            }
        };
        for &i in kept {
            while next_corner < 4 && corners[next_corner] <= i {
                take(corners[next_corner], &mut self.kept_mark, &mut self.kept);
                next_corner += 1;
            }
            take(i, &mut self.kept_mark, &mut self.kept);
        }
        for &c in &corners[next_corner..] {
            take(c, &mut self.kept_mark, &mut self.kept);
        }
        if !self.kept.is_sorted() {
            self.kept.sort_unstable();
        }
        Ok(())
    }

    /// Scores the kept set of `state` with the kept points `remove` taken out and the grid
    /// points `insert` added, by editing `state` in place (see `edit/`). The result is
    /// bit for bit what [`score`](Self::score) gives for the new kept set, and `state` becomes
    /// that set's mesh. `state` must come from [`score_into`](Self::score_into) on this
    /// evaluator (or earlier edits). Each index of `remove` must be kept and not a corner, each
    /// of `insert` not kept (after the removals); on such an error `state` is unchanged.
    pub fn edit(
        &mut self,
        state: &mut MeshState,
        remove: &[u32],
        insert: &[u32],
    ) -> Result<Score, EvaluateError> {
        state.edit(&self.hf, remove, insert, &mut self.scratch)
    }

    /// Scores, into `state`, the child that keeps `a`'s kept points where the bitset `from_b`
    /// (bit `i` of word `i / 64` for grid point `i`) is clear and `b`'s where it is set, by
    /// reusing the triangles and errors of both parents' meshes (see `compose/`). The result
    /// is bit for bit what [`score`](Self::score) gives for the child's kept set, and `state`
    /// becomes its mesh, ready to edit. `a` and `b` must come from this evaluator and have their
    /// disc boxes filled ([`MeshState::ensure_discs`]); otherwise, or when a guard fails, returns
    /// `None` and `state` is left unscored (score it another way).
    pub fn compose(
        &mut self,
        state: &mut MeshState,
        a: &MeshState,
        b: &MeshState,
        from_b: &[u64],
    ) -> Option<Score> {
        state.compose(&self.hf, a, b, from_b, &mut self.compose_scratch)
    }

    /// [`compose`](Self::compose) for the child that takes part `p` of `classes` (a tiling of
    /// the grid by rectangles, such as a crossover's blocks) from `b` where bit `p` of `levels`
    /// is set and from `a` elsewhere. `classes` classifies both parents' triangles once for all
    /// such children ([`PartClasses::new`]), so each child costs one mask test per parent
    /// triangle where [`compose`](Self::compose) searches their circles. The same mesh and bits
    /// as [`compose`](Self::compose); `None` also when `classes` was made for other meshes
    /// (or for these before they changed).
    ///
    /// ```
    /// use paretomesh::evaluator::{Evaluator, MeshState, PartClasses};
    /// use paretomesh::heightfield::Heightfield;
    /// use std::sync::Arc;
    /// let z: Vec<f64> = (0..25).map(|i| ((i * 7) % 5) as f64).collect();
    /// let hf = Arc::new(Heightfield::new(5, 5, z).unwrap());
    /// let mut ev = Evaluator::new(hf.clone());
    /// let (mut a, mut b) = (MeshState::default(), MeshState::default());
    /// ev.score_into(&[6, 12, 18], &mut a).unwrap();
    /// ev.score_into(&[8, 16], &mut b).unwrap();
    /// a.ensure_discs();
    /// b.ensure_discs();
    /// // Two parts: columns 0–1 and columns 2–4.
    /// let classes = PartClasses::new(&hf, &a, &b, &[[0, 0, 2, 5], [2, 0, 5, 5]]).unwrap();
    /// // Part 0 from A (its point 6), part 1 from B (its point 8).
    /// let mut child = MeshState::default();
    /// let score = ev.compose_parts(&mut child, &a, &b, &classes, 0b10).unwrap();
    /// assert_eq!(score, ev.score(&[6, 8]).unwrap());
    /// ```
    pub fn compose_parts(
        &mut self,
        state: &mut MeshState,
        a: &MeshState,
        b: &MeshState,
        classes: &PartClasses,
        levels: u32,
    ) -> Option<Score> {
        let crossing = Crossing {
            hf: &self.hf,
            parents: [a, b],
            classes,
        };
        let memo = &mut self.row_scratch.memo;
        state.compose_parts(crossing, levels, &mut self.compose_scratch, memo)
    }

    /// The score [`compose_parts`](Self::compose_parts) gives for `levels`, bit for bit, without
    /// building the child's mesh: from what the children of `classes` share, which `scores`
    /// holds once [prepared](PartScores::prepare) for the same parents (see
    /// `part_scores/`). `None` when `scores` or `classes` were made for other meshes, or when a
    /// guard fails.
    ///
    /// ```
    /// use paretomesh::evaluator::{Crossing, Evaluator, MeshState, PartClasses, PartScores};
    /// use paretomesh::heightfield::Heightfield;
    /// use std::sync::Arc;
    /// let z: Vec<f64> = (0..25).map(|i| ((i * 7) % 5) as f64).collect();
    /// let hf = Arc::new(Heightfield::new(5, 5, z).unwrap());
    /// let mut ev = Evaluator::new(hf.clone());
    /// let (mut a, mut b) = (MeshState::default(), MeshState::default());
    /// ev.score_into(&[6, 12, 18], &mut a).unwrap();
    /// ev.score_into(&[8, 16], &mut b).unwrap();
    /// a.ensure_discs();
    /// b.ensure_discs();
    /// let classes = PartClasses::new(&hf, &a, &b, &[[0, 0, 2, 5], [2, 0, 5, 5]]).unwrap();
    /// let mut scores = PartScores::default();
    /// let crossing = Crossing { hf: &hf, parents: [&a, &b], classes: &classes };
    /// assert!(scores.prepare(crossing));
    /// // Part 0 from A (its point 6), part 1 from B (its point 8).
    /// let score = ev.score_parts(&a, &b, &classes, &mut scores, 0b10).unwrap();
    /// assert_eq!(score, ev.score(&[6, 8]).unwrap());
    /// ```
    pub fn score_parts(
        &mut self,
        a: &MeshState,
        b: &MeshState,
        classes: &PartClasses,
        scores: &mut PartScores,
        levels: u32,
    ) -> Option<Score> {
        let crossing = Crossing {
            hf: &self.hf,
            parents: [a, b],
            classes,
        };
        scores.score(crossing, levels, &mut self.row_scratch)
    }

    /// [`score_parts`](Self::score_parts) for that child with `changes` made to its kept
    /// points (a mutant of it), bit for bit the changed set's fresh score, still without a
    /// mesh (`PartScores::score_changed`).
    pub(crate) fn score_parts_changed(
        &mut self,
        a: &MeshState,
        b: &MeshState,
        classes: &PartClasses,
        scores: &mut PartScores,
        levels: u32,
        changes: Changes<'_>,
    ) -> Option<Score> {
        let crossing = Crossing {
            hf: &self.hf,
            parents: [a, b],
            classes,
        };
        scores.score_changed(crossing, levels, changes, &mut self.row_scratch)
    }

    /// The score of the mesh that `base` (scored by this evaluator, its lookups filled:
    /// [`MeshState::ensure_discs`]) becomes with `changes` made to its kept points: bit for bit
    /// what [`edit`](Self::edit)ing a copy of it gives, without the copy or the edit (its
    /// triangles but those the changes drop are reused, and the region they leave is tiled and
    /// rasterised). `None` when `base` is not ready, a removed point is a corner or not kept,
    /// an inserted one is kept, or a guard fails: score it another way.
    pub(crate) fn score_mutant(&mut self, base: &MeshState, changes: Changes<'_>) -> Option<Score> {
        part_scores::score_mutant(&self.hf, base, changes, &mut self.row_scratch)
    }

    /// The kept points of the last [`score`](Self::score) call, increasing, corners included.
    pub fn kept(&self) -> &[u32] {
        &self.kept
    }

    /// The triangles of the last scored mesh.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.state.triangles()
    }

    /// Scores any valid triangulation of grid points, Delaunay or not, so that meshes from other
    /// tools are compared on equal terms. The triangles must cover the grid rectangle exactly
    /// once, edge to edge (no overlaps, holes or T-junctions); either orientation is accepted.
    pub fn score_triangulation(&mut self, triangles: &[[u32; 3]]) -> Result<Score, EvaluateError> {
        let n = self.hf.len();
        let w = self.hf.width() as i64;
        let h = self.hf.height() as i64;
        let lattice = predicates::Lattice::new(self.hf.width());
        let point = |i: u32| lattice.point(i);
        let mut oriented = Vec::with_capacity(triangles.len());
        let mut area = 0i64;
        for &tri in triangles {
            check_indices(&tri, n)?;
            let o = predicates::orient(point(tri[0]), point(tri[1]), point(tri[2]));
            if o == 0 {
                return Err(EvaluateError::DegenerateTriangle { triangle: tri });
            }
            area += o.abs();
            oriented.push(if o > 0 { tri } else { [tri[0], tri[2], tri[1]] });
        }
        let expected = 2 * (w - 1) * (h - 1);
        let mut edges: Vec<(u32, u32)> = oriented
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .collect();
        edges.sort_unstable();
        if let Some(pair) = edges.windows(2).find(|p| p[0] == p[1]) {
            return Err(EvaluateError::OverlappingEdge {
                from: pair[0].0,
                to: pair[0].1,
            });
        }
        let grid = Grid {
            width: w,
            height: h,
            z: self.hf.z(),
        };
        for &(a, b) in &edges {
            let reverse_exists = edges.binary_search(&(b, a)).is_ok();
            if !reverse_exists && !grid.on_border(point(a), point(b)) {
                return Err(EvaluateError::OpenEdge { from: a, to: b });
            }
        }
        if area != expected {
            return Err(EvaluateError::WrongArea {
                found: area,
                expected,
            });
        }
        let mesh = self.state.mesh_mut();
        mesh.vertices.clear();
        mesh.twin.clear();
        for t in &oriented {
            mesh.vertices.extend_from_slice(t);
        }
        // Not a linked Delaunay triangulation: this state cannot be edited.
        Ok(self.state.score_once(&self.hf))
    }
}
