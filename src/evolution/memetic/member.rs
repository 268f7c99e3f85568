//! A scored kept set with its mesh, the local edits the operators make to one, and how the
//! archive receives them.

use super::guide::Guide;
use crate::evaluator::{Evaluator, GridLookups, MeshState, Score};
use crate::front::Front;
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;

/// Per-grid-point arrays lent to the members being edited ([`Member::unstow`]) and taken back
/// from those set aside ([`Member::stow`]): a population member that waits for its next use
/// holds its mesh and kept list only, so a member's memory grows with its mesh, not with the
/// grid.
#[derive(Debug, Default)]
pub(crate) struct LookupPool {
    free: Vec<GridLookups>,
}

/// Arrays a [`LookupPool`] keeps at most: a child, its two parents and one spare.
pub(crate) const POOLED_LOOKUPS: usize = 4;

impl LookupPool {
    fn take(&mut self) -> GridLookups {
        self.free.pop().unwrap_or_default()
    }

    fn give(&mut self, lookups: GridLookups) {
        if self.free.len() < POOLED_LOOKUPS {
            self.free.push(lookups);
        }
    }
}

/// A population member (or the subject of local search): kept points, score and mesh.
#[derive(Clone, Debug)]
pub(crate) struct Member {
    /// Kept grid points, increasing, corners included.
    pub kept: Vec<u32>,
    /// Its score, bit for bit [`Evaluator::score`]'s.
    pub score: Score,
    /// Its mesh, ready to edit.
    pub state: MeshState,
    /// Its guide, made when an operator first reads it.
    pub guide: Option<Guide>,
    /// Non-domination rank in the population (0 = non-dominated).
    pub rank: usize,
    /// Crowding distance within its rank.
    pub crowding: f64,
}

impl Member {
    /// Scores `kept` (increasing, corners included) from scratch: one evaluation.
    pub(crate) fn fresh(evaluator: &mut Evaluator, kept: Vec<u32>) -> Self {
        let mut state = MeshState::default();
        let score = evaluator
            .score_into(&kept, &mut state)
            .expect("kept points are grid indices");
        Self::scored(kept, score, state)
    }

    /// A member from a kept set already scored into `state`.
    pub(crate) fn scored(kept: Vec<u32>, score: Score, state: MeshState) -> Self {
        Self {
            kept,
            score,
            state,
            guide: None,
            rank: 0,
            crowding: 0.0,
        }
    }

    /// (the run's error, T), both minimised.
    pub(crate) fn pair(&self, measure: ErrorMeasure) -> [f64; 2] {
        measure.objectives(&self.score)
    }

    /// Its guide, made now if it was not.
    pub(crate) fn guide(&mut self, hf: &Heightfield) -> &Guide {
        if self.guide.is_none() {
            self.guide = Some(Guide::of(hf, &self.state, &self.kept));
        }
        self.guide.as_ref().expect("just made")
    }

    /// Fills the lookups [`Evaluator::score_mutant`] reads, if stale (an edit or a copy leaves
    /// them so).
    pub(crate) fn ready_for_trials(&mut self) {
        self.state.ensure_lookups();
    }

    /// Sets the member aside: its mesh's per-grid-point arrays go back to `pool`
    /// ([`MeshState::detach_lookups`]). It must be [unstowed](Self::unstow) before it is edited,
    /// tried or composed from; its guide and score stay.
    pub(crate) fn stow(&mut self, pool: &mut LookupPool) {
        if let Some(lookups) = self.state.detach_lookups() {
            pool.give(lookups);
        }
    }

    /// Makes a stowed member editable again, with arrays from `pool` (a pass over its mesh).
    pub(crate) fn unstow(&mut self, pool: &mut LookupPool) {
        if !self.state.has_lookups() {
            self.state.attach_lookups(pool.take());
        }
    }

    /// Applies `edit` to the mesh ([`Evaluator::edit`], one evaluation) and the kept list.
    pub(crate) fn apply(&mut self, evaluator: &mut Evaluator, edit: &Edit) {
        self.score = evaluator
            .edit(&mut self.state, &edit.remove, &edit.insert)
            .expect("operators remove kept non-corner points and insert free ones");
        edit.apply_to(&mut self.kept);
        self.guide = None;
    }
}

/// A local change of a kept set: points to remove (kept, not corners) and points to insert
/// (not kept).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Edit {
    /// Kept points that leave.
    pub remove: Vec<u32>,
    /// Free points that join.
    pub insert: Vec<u32>,
}

impl Edit {
    /// Makes the change on an increasing kept list, which stays increasing.
    pub(crate) fn apply_to(&self, kept: &mut Vec<u32>) {
        for r in &self.remove {
            if let Ok(at) = kept.binary_search(r) {
                kept.remove(at);
            }
        }
        for &i in &self.insert {
            if let Err(at) = kept.binary_search(&i) {
                kept.insert(at, i);
            }
        }
    }
}

/// Offers a scored kept set to the archive, copying the kept list only when it enters
/// ([`Front::offer_score`]).
pub(crate) fn offer(archive: &mut Front, kept: &[u32], score: &Score) -> bool {
    archive.offer_score(*score, || kept.to_vec())
}

/// Is grid point `i` on the grid's border? Swapping a border point for an interior one (or
/// back) changes the triangle count by one, so the fixed-T moves keep the two apart.
pub(crate) fn on_border(hf: &Heightfield, i: u32) -> bool {
    let (x, y) = hf.coords(i);
    x == 0 || y == 0 || x + 1 == hf.width() || y + 1 == hf.height()
}
