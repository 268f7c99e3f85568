//! Exact-cost decimation (the drop heuristic, Lee 1991): from a dense greedy mesh, remove one
//! vertex at a time, always the one whose removal raises E_sum least per triangle it saves,
//! down to the corners, recording the mesh every [`RECORD_RATIO`] in T.
//!
//! Why: greedy insertion decides where a point goes knowing only the mesh so far, so a dense
//! greedy mesh holds many points that later insertions made nearly useless. Removing points
//! by their measured cost from a mesh about twice as dense as the target keeps the points
//! that the surface needs at that density; on sum-type errors it gives meshes 10–20 % better
//! than greedy insertion at the same T, which no swap search on the greedy mesh reaches in the
//! same evaluations.
//!
//! Each cost is a trial removal scored incrementally ([`mutation::trial`]). A removal changes
//! only the stars of its neighbours, so only their costs are scored again; the queue is lazy,
//! with a version per vertex that marks older entries stale.
//!
//! Unit: [`INITIAL_TRIALS`] trials of the starting mesh's costs, or one removal with its
//! neighbours' new costs (about seven evaluations).

use super::member::{Edit, Member};
use super::mutation;
use crate::evaluator::{Evaluator, Score};
use crate::heightfield::Heightfield;
use crate::lazy_queue::Entry;
use crate::measure::ErrorMeasure;
use std::collections::BinaryHeap;

/// The mesh is recorded whenever its T has fallen to this fraction of the last recorded T (or
/// below), so the front it leaves has no gap wider than 2 % in T.
pub const RECORD_RATIO: f64 = 0.98;

/// Kept points of the starting mesh whose first costs a unit scores (corners are skipped).
pub const INITIAL_TRIALS: usize = 32;

/// The densest mesh decimation starts from: half the full mesh, at most [`START_CAP`]
/// triangles. Twice a target's density is enough for the removals to choose well (starting
/// from the full mesh gives the same errors below a quarter of it), and the cap bounds the
/// cost on large grids, where each start vertex costs about seven evaluations.
pub fn start_triangles(hf: &Heightfield) -> usize {
    (hf.full_triangles() / 2).min(START_CAP)
}

/// See [`start_triangles`]: 2¹⁶ triangles, half a 257×257 grid's full mesh.
pub const START_CAP: usize = 1 << 16;

/// A decimation in progress; see the module doc.
pub struct Decimation {
    member: Member,
    /// The position in the starting mesh's kept list of the next vertex whose first cost is
    /// to be scored (the list does not change until every first cost is).
    next_first: usize,
    /// Removal costs, cheapest first: the key is the cost negated, `point` and `slot` the
    /// vertex, `stamp` its version when the cost was scored (ties go to the smaller vertex).
    queue: BinaryHeap<Entry>,
    /// Per grid point, the version of its latest queued cost: one array for the run, like the
    /// greedy sweeps' own state.
    version: Vec<u32>,
    /// The mesh is recorded once its T is at most this.
    next_record: usize,
    evaluations: u64,
    done: bool,
    /// The error whose rise per triangle saved is a removal's cost.
    measure: ErrorMeasure,
}

impl Decimation {
    /// Decimation of the kept set `kept` (increasing, corners included; one evaluation).
    pub fn new(evaluator: &mut Evaluator, kept: Vec<u32>, measure: ErrorMeasure) -> Self {
        let grid_len = evaluator.heightfield().len();
        let member = Member::fresh(evaluator, kept);
        let mut run = Self {
            measure,
            next_record: member.score.t,
            member,
            next_first: 0,
            queue: BinaryHeap::new(),
            version: vec![0; grid_len],
            evaluations: 1,
            done: false,
        };
        if run.member.kept.len() <= 4 {
            // Only the corners: nothing to remove.
            run.finish();
        }
        run
    }

    /// The mesh as decimated so far (the tests hold each removal to brute force).
    #[cfg(test)]
    pub fn member(&self) -> &Member {
        &self.member
    }

    /// Evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Down to the corners?
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// One unit (see the module doc). Hands each recorded mesh (its kept set and score) to
    /// `record`, the starting mesh first.
    pub fn unit(&mut self, evaluator: &mut Evaluator, mut record: impl FnMut(&[u32], &Score)) {
        if self.done {
            return;
        }
        self.member.ready_for_trials();
        let corners = evaluator.heightfield().corners();
        if self.next_first < self.member.kept.len() {
            if self.next_first == 0 {
                self.record_if_due(&mut record);
            }
            let end = (self.next_first + INITIAL_TRIALS).min(self.member.kept.len());
            for k in self.next_first..end {
                let v = self.member.kept[k];
                if !corners.contains(&v) {
                    self.queue_cost(evaluator, v);
                }
            }
            self.next_first = end;
            return;
        }
        let Some(v) = self.cheapest() else {
            self.finish();
            return;
        };
        let neighbours = self.member.state.neighbours(v);
        self.member.apply(
            evaluator,
            &Edit {
                remove: vec![v],
                insert: Vec::new(),
            },
        );
        self.evaluations += 1;
        self.member.ready_for_trials();
        for u in neighbours {
            if !corners.contains(&u) {
                self.queue_cost(evaluator, u);
            }
        }
        self.record_if_due(&mut record);
        if self.queue.is_empty() {
            self.finish();
        }
    }

    /// Ends the run and lets go of what only the removals needed: the per-grid-point versions
    /// and the mesh's per-grid-point arrays (the run is kept for its count of evaluations).
    fn finish(&mut self) {
        self.done = true;
        self.queue = BinaryHeap::new();
        self.version = Vec::new();
        self.member.state.detach_lookups();
    }

    /// Pops stale entries until the cheapest current one, and returns its vertex.
    fn cheapest(&mut self) -> Option<u32> {
        while let Some(entry) = self.queue.pop() {
            let v = entry.point;
            if entry.stamp == self.version[v as usize] && self.member.state.is_kept(v) {
                return Some(v);
            }
        }
        None
    }

    /// Scores removing `v` and queues its cost, superseding any earlier one.
    fn queue_cost(&mut self, evaluator: &mut Evaluator, v: u32) {
        let edit = Edit {
            remove: vec![v],
            insert: Vec::new(),
        };
        let after = mutation::trial(evaluator, &self.member, &edit);
        self.evaluations += 1;
        let saved = self.member.score.t.saturating_sub(after.t).max(1);
        let m = self.measure;
        let cost = (m.of(&after) - m.of(&self.member.score)) / saved as f64;
        let version = &mut self.version[v as usize];
        *version = version.wrapping_add(1);
        self.queue.push(Entry {
            key: -cost,
            point: v,
            slot: v,
            stamp: *version,
        });
    }

    fn record_if_due(&mut self, record: &mut impl FnMut(&[u32], &Score)) {
        let t = self.member.score.t;
        if t <= self.next_record {
            record(&self.member.kept, &self.member.score);
            self.next_record = ((t as f64 * RECORD_RATIO) as usize).min(t.saturating_sub(1));
        }
    }
}
