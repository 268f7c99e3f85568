//! A priority-queue entry with lazy invalidation, shared by both baselines and the memetic
//! method's decimation.

use std::cmp::Ordering;

/// One queued candidate: the highest `key` pops first, ties go to the smaller grid `point`
/// (which makes every run deterministic). `slot` names the triangle or vertex the entry was
/// computed for and `stamp` the version of that slot at the time; an entry whose stamp no longer
/// matches is stale and skipped when popped.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    pub key: f64,
    pub point: u32,
    pub slot: u32,
    pub stamp: u32,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        self.key
            .total_cmp(&other.key)
            .then_with(|| other.point.cmp(&self.point))
            .then_with(|| other.slot.cmp(&self.slot))
            .then_with(|| self.stamp.cmp(&other.stamp))
    }
}
