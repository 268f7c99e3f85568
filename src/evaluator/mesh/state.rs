//! A scored mesh: a kept set's canonical triangulation with each triangle's error totals, and
//! the lookups the compositions and mutants of it need.

use super::canonical_triangulation::{NONE, Triangulation, copy_fitted};
use super::disc_box::DiscBox;
use crate::evaluator::exact::fixed_point::ErrorTotals;
use crate::evaluator::exact::predicates::{self, GridPoint, Lattice};
use crate::evaluator::score::Score;
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// A kept set's canonical triangulation with the error of every grid point: what
/// [`Evaluator::score_into`](crate::evaluator::Evaluator::score_into) makes and
/// [`Evaluator::edit`](crate::evaluator::Evaluator::edit) changes. Cloning one is a plain copy (use
/// `clone_from` to reuse the buffers).
#[derive(Debug, Default)]
pub struct MeshState {
    /// The height field it was scored on (`None` until scored).
    pub(crate) hf: Option<Arc<Heightfield>>,
    pub(crate) kept: Vec<bool>,
    pub(crate) mesh: Triangulation,
    /// Per triangle slot, the error totals of the grid points it owns (its vertices excluded).
    pub(crate) totals: Vec<ErrorTotals>,
    /// Per kept grid point, a triangle slot of its star: exact after every build, edit or
    /// composition (walks and star walks start there). Unspecified for other points.
    pub(crate) hint: Vec<u32>,
    pub(crate) score: Option<Score>,
    /// Per triangle slot, the grid box of its circumcircle's disc (see
    /// [`compose`](crate::evaluator::compose)); valid only while `discs_valid`. Filled on demand, not by
    /// builds and edits, which would pay for it on every triangle.
    pub(crate) discs: Vec<DiscBox>,
    pub(crate) discs_valid: bool,
    /// The kept points as a bitset (bit `i` of word `i / 64`) and as a summed-area table
    /// (`(W + 1) × (H + 1)`, kept points in columns < x of rows < y at (y, x)); valid only while
    /// `lookup_valid`. Filled on demand with the disc boxes, for the crossovers this mesh is a
    /// parent of.
    pub(crate) kept_bits: Vec<u64>,
    pub(crate) kept_sat: Vec<u32>,
    pub(crate) lookup_valid: bool,
    /// Changes whenever the mesh does (a new number from [`next_revision`] at every scoring),
    /// so that what was derived from one mesh ([`PartClasses`](crate::evaluator::PartClasses))
    /// can tell it from later ones; 0 until scored. A copy keeps it: it is the same mesh.
    pub(crate) revision: u64,
}

/// A number no mesh state had before (in this process).
pub(crate) fn next_revision() -> u64 {
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

    pub(crate) fn mesh_mut(&mut self) -> &mut Triangulation {
        &mut self.mesh
    }

    /// Marks this state as not editable (its mesh is not a linked Delaunay triangulation, or
    /// its per-point errors and hints were not written), and its disc boxes as stale.
    pub(crate) fn forget(&mut self) {
        self.hf = None;
        self.revision = 0;
        self.discs_valid = false;
        self.lookup_valid = false;
    }

    /// The live triangle whose closed area holds `p`, by a visibility walk from slot `start`
    /// (any slot: a dead one forwards to a live one nearby, an out-of-range one starts from the
    /// first live triangle), with an exhaustive search behind the walk's step cap.
    pub(crate) fn locate(&self, lattice: Lattice, start: u32, p: GridPoint) -> u32 {
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

    /// Fills the disc boxes of this state's triangles, and its kept points' bitset and
    /// summed-area table, if they are stale (a build or an edit leaves them so). A parent is
    /// composed from many times, so this is paid once per parent.
    pub fn ensure_discs(&mut self) {
        let Some(hf) = self.hf.clone() else {
            return;
        };
        let (w, h) = (hf.width(), hf.height());
        if !self.discs_valid {
            let lattice = Lattice::new(w);
            self.discs.clear();
            self.discs.extend((0..self.mesh.len()).map(|t| {
                let p = self.mesh.triangle(t).map(|i| lattice.point(i));
                DiscBox::of(p, w, h)
            }));
            self.discs_valid = true;
        }
        self.ensure_lookups();
    }

    /// Is this state scored on `hf` with its disc boxes filled, ready to be a composition's
    /// parent?
    pub(crate) fn is_composable_on(&self, hf: &Arc<Heightfield>) -> bool {
        self.hf.as_ref().is_some_and(|h| Arc::ptr_eq(h, hf))
            && self.score.is_some()
            && self.discs_valid
    }

    /// Fills this state's kept points' bitset and summed-area table if they are stale (part of
    /// [`ensure_discs`](Self::ensure_discs), and all that
    /// [`Evaluator::score_mutant`](crate::evaluator::Evaluator::score_mutant) needs).
    pub fn ensure_lookups(&mut self) {
        let Some(hf) = self.hf.clone() else {
            return;
        };
        let (w, h) = (hf.width(), hf.height());
        if !self.lookup_valid {
            let kept = &self.kept[..w * h];
            self.kept_bits.clear();
            self.kept_bits.extend(kept.chunks(64).map(|c| {
                c.iter()
                    .enumerate()
                    .fold(0u64, |word, (k, &b)| word | (u64::from(b) << k))
            }));
            let sat = &mut self.kept_sat;
            sat.clear();
            sat.resize((w + 1) * (h + 1), 0);
            for (y, row) in kept.chunks_exact(w).enumerate() {
                let (below, here) = sat[y * (w + 1)..].split_at_mut(w + 1);
                let mut run = 0;
                for (x, &k) in row.iter().enumerate() {
                    run += u32::from(k);
                    here[x + 1] = below[x + 1] + run;
                }
            }
            self.lookup_valid = true;
        }
    }
}
