//! A priority queue with at most one entry per slot, updated in place: greedy insertion's
//! queue of triangles.
//!
//! Why not a [`BinaryHeap`](std::collections::BinaryHeap) with stale entries skipped on pop
//! (as [`queue::Entry`](super::queue::Entry) is used elsewhere): greedy insertion re-queues
//! every triangle an insertion changes and pops only the best, so the stale entries of the
//! changed triangles pile up (several per insertion) and a large grid's heap grows to millions
//! of mostly dead entries, every push and pop walking a tree several times deeper and far
//! larger than the cache. Here a slot's entry is replaced or removed where it stands
//! (positions are tracked per slot), so the heap holds one entry per live triangle.
//!
//! Order: the highest `key` first (by [`f64::total_cmp`]), ties to the smaller `point`, as
//! [`Entry`](super::queue::Entry) orders them; callers never queue two entries with the same
//! key and point, so the top is the same as that of a lazy heap holding the same live entries.

use std::cmp::Ordering;

/// Not in the heap.
const ABSENT: u32 = u32::MAX;

/// Children per node. Why four: an entry replaced by a smaller key (every triangle an insertion
/// splits) sinks from near the top to the bottom, and a large grid's heap is far larger than
/// the cache; four children (64 bytes, about one cache line) halve the levels it crosses.
const ARITY: usize = 4;

/// One queued entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Item {
    /// The priority.
    pub key: f64,
    /// The grid point it proposes.
    pub point: u32,
    /// The slot (triangle) it belongs to.
    pub slot: u32,
}

impl Item {
    /// Does `self` come out before `other`?
    #[inline(always)]
    fn before(&self, other: &Self) -> bool {
        match self.key.total_cmp(&other.key) {
            Ordering::Greater => true,
            Ordering::Less => false,
            Ordering::Equal => self.point < other.point,
        }
    }
}

/// See the module docs.
#[derive(Clone, Debug, Default)]
pub(crate) struct SlotHeap {
    heap: Vec<Item>,
    /// Position of each slot's entry in `heap`, or `ABSENT`.
    position: Vec<u32>,
}

impl SlotHeap {
    /// Number of queued entries.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.heap.len()
    }

    /// The first entry, if any.
    #[inline]
    pub(crate) fn top(&self) -> Option<Item> {
        self.heap.first().copied()
    }

    /// The key of `slot`'s entry, or 0 when it has none.
    #[inline]
    pub(crate) fn key_of(&self, slot: u32) -> f64 {
        match self.position.get(slot as usize) {
            Some(&at) if at != ABSENT => self.heap[at as usize].key,
            _ => 0.0,
        }
    }

    /// The queued entries, in no particular order.
    #[cfg(test)]
    pub(crate) fn items(&self) -> &[Item] {
        &self.heap
    }

    /// Queues `item`, replacing its slot's entry if there is one.
    pub(crate) fn set(&mut self, item: Item) {
        let slot = item.slot as usize;
        if self.position.len() <= slot {
            self.position.resize(slot + 1, ABSENT);
        }
        let at = self.position[slot];
        if at == ABSENT {
            let at = self.heap.len();
            self.heap.push(item);
            self.position[slot] = at as u32;
            self.up(at);
        } else {
            let at = at as usize;
            let old = std::mem::replace(&mut self.heap[at], item);
            if item.before(&old) {
                self.up(at);
            } else {
                self.down(at);
            }
        }
    }

    /// Removes `slot`'s entry, if there is one.
    pub(crate) fn remove(&mut self, slot: u32) {
        let Some(&at) = self.position.get(slot as usize) else {
            return;
        };
        if at == ABSENT {
            return;
        }
        self.position[slot as usize] = ABSENT;
        let at = at as usize;
        let last = self
            .heap
            .pop()
            .expect("a slot with a position has an entry");
        if at < self.heap.len() {
            // The last entry fills the hole and moves whichever way it must.
            self.heap[at] = last;
            self.position[last.slot as usize] = at as u32;
            if at > 0 && last.before(&self.heap[(at - 1) / ARITY]) {
                self.up(at);
            } else {
                self.down(at);
            }
        }
    }

    /// Removes and returns the first entry.
    pub(crate) fn pop(&mut self) -> Option<Item> {
        let top = self.top()?;
        self.remove(top.slot);
        Some(top)
    }

    fn up(&mut self, mut at: usize) {
        let item = self.heap[at];
        while at > 0 {
            let parent = (at - 1) / ARITY;
            let p = self.heap[parent];
            if !item.before(&p) {
                break;
            }
            self.heap[at] = p;
            self.position[p.slot as usize] = at as u32;
            at = parent;
        }
        self.heap[at] = item;
        self.position[item.slot as usize] = at as u32;
    }

    fn down(&mut self, mut at: usize) {
        let item = self.heap[at];
        let n = self.heap.len();
        loop {
            let first = ARITY * at + 1;
            if first >= n {
                break;
            }
            let mut child = first;
            for c in first + 1..(first + ARITY).min(n) {
                if self.heap[c].before(&self.heap[child]) {
                    child = c;
                }
            }
            let c = self.heap[child];
            if !c.before(&item) {
                break;
            }
            self.heap[at] = c;
            self.position[c.slot as usize] = at as u32;
            at = child;
        }
        self.heap[at] = item;
        self.position[item.slot as usize] = at as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn pops_in_the_order_of_a_sorted_list_after_random_updates() {
        // Random sets, replacements and removals on a few hundred slots, with keys drawn from a
        // handful of values (so ties on the key are common and the point decides); then every
        // pop must give the best remaining entry of a plain map kept alongside.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x51e4);
        for round in 0..50 {
            let mut heap = SlotHeap::default();
            let mut live: Vec<Option<Item>> = vec![None; 300];
            for _ in 0..2000 {
                let slot = rng.random_range(0..300u32);
                if rng.random_range(0..4) == 0 {
                    heap.remove(slot);
                    live[slot as usize] = None;
                } else {
                    // Points unique per slot and key pair, as greedy insertion's are.
                    let item = Item {
                        key: [-1.0, 0.0, 0.5, 2.0, 7.25][rng.random_range(0..5)],
                        point: slot * 7 + rng.random_range(0..7),
                        slot,
                    };
                    heap.set(item);
                    live[slot as usize] = Some(item);
                }
                let best = live
                    .iter()
                    .flatten()
                    .copied()
                    .reduce(|a, b| if b.before(&a) { b } else { a });
                assert_eq!(heap.top(), best, "round {round}");
            }
            let mut expected: Vec<Item> = live.iter().flatten().copied().collect();
            expected.sort_by(|a, b| b.key.total_cmp(&a.key).then_with(|| a.point.cmp(&b.point)));
            assert_eq!(heap.len(), expected.len());
            let popped: Vec<Item> = std::iter::from_fn(|| heap.pop()).collect();
            assert_eq!(popped, expected, "round {round}");
        }
    }
}
