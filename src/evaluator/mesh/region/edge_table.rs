//! The edges gift wrapping has found, by their ends, and the queue of those still to wrap.

/// "No claim yet" in an [`EdgeTable`] direction.
pub(super) const VACANT: u32 = u32::MAX;

/// An [`EdgeTable`] slot nobody uses.
pub(super) const EMPTY: u64 = u64::MAX;

/// A queued edge's slot in the [`EdgeTable`] and which of its directions it is: the slot
/// times two plus the direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct Queued(pub(super) u32);

impl Queued {
    /// The direction of `slot` opposite to `d`.
    #[inline(always)]
    pub(super) fn across(slot: usize, d: usize) -> Self {
        Self((2 * slot + (1 - d)) as u32)
    }

    /// The slot and the direction.
    #[inline(always)]
    pub(super) fn slot(self) -> (usize, usize) {
        ((self.0 >> 1) as usize, (self.0 & 1) as usize)
    }
}

/// Undirected edges between local indices with a value per direction ([`VACANT`] until
/// claimed), by open addressing, and the queue of directed edges that still need a triangle on
/// their left. Why undirected: claiming one direction returns the other's value in the same
/// probe, so twins are linked as they are made; and a queued edge keeps its slot, so an edge
/// claimed since it was queued costs one load.
#[derive(Clone, Debug, Default)]
pub(super) struct EdgeTable {
    /// Per slot: the key lo << 32 | hi of the edge between lo < hi (or [`EMPTY`]), and the
    /// values of lo → hi (low half) and hi → lo (high half).
    pub(super) slots: Vec<(u64, u64)>,
    /// The slots in use (the first `count`), to empty them again; as long as `slots`.
    pub(super) used: Vec<u32>,
    pub(super) count: usize,
    /// 64 − log2 of the number of slots.
    pub(super) shift: u32,
    /// Directed edges (local indices) that still need a triangle on their left.
    pub(super) queue: Vec<(u32, u32, Queued)>,
}

impl EdgeTable {
    /// Empties the table and the queue, with room for about `expected` edges.
    pub(super) fn reset(&mut self, expected: usize) {
        for &s in &self.used[..self.count] {
            self.slots[s as usize].0 = EMPTY;
        }
        self.count = 0;
        self.queue.clear();
        let want = (2 * expected.max(16)).next_power_of_two();
        if self.slots.len() < want {
            self.slots.clear();
            self.slots.resize(want, (EMPTY, u64::MAX));
            self.used.resize(want, 0);
        }
        self.shift = 64 - self.slots.len().trailing_zeros();
    }

    /// The key of the edge between `x` and `y`, and which of its values is `x → y`'s.
    #[inline(always)]
    pub(super) fn key(x: u32, y: u32) -> (u64, usize) {
        if x < y {
            ((u64::from(x) << 32) | u64::from(y), 0)
        } else {
            ((u64::from(y) << 32) | u64::from(x), 1)
        }
    }

    /// The slot holding `key`, or the empty slot where it would go.
    #[inline(always)]
    pub(super) fn find(&self, key: u64) -> usize {
        let mask = self.slots.len() - 1;
        let mut s = (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> self.shift) as usize;
        loop {
            let k = self.slots[s].0;
            if k == key || k == EMPTY {
                return s;
            }
            s = (s + 1) & mask;
        }
    }

    /// The slot of the edge between `x` and `y` (made, both directions vacant, if new) and
    /// which of its values is `x → y`'s.
    #[inline(always)]
    pub(super) fn entry(&mut self, x: u32, y: u32) -> (usize, usize) {
        if 2 * (self.count + 1) > self.slots.len() {
            self.grow();
        }
        let (key, d) = Self::key(x, y);
        let s = self.find(key);
        // New or not is data: written either way, and the slot counted in use only if new.
        let slot = &mut self.slots[s];
        let new = slot.0 == EMPTY;
        // Both vacant (all ones) if new.
        slot.1 |= u64::from(new).wrapping_neg();
        slot.0 = key;
        self.used[self.count] = s as u32;
        self.count += usize::from(new);
        (s, d)
    }

    /// Claims direction `d` of `slot` for `value` (the slot from [`entry`](Self::entry) or the
    /// queue, with no entry since): the other direction's value ([`VACANT`] if unclaimed), or
    /// `None` if this one is claimed already (two triangles left of one edge).
    #[inline(always)]
    pub(super) fn claim(&mut self, slot: usize, d: usize, value: u32) -> Option<u32> {
        let values = &mut self.slots[slot].1;
        let shift = 32 * d as u32;
        if (*values >> shift) as u32 != VACANT {
            return None;
        }
        *values = (*values & !(u64::from(u32::MAX) << shift)) | (u64::from(value) << shift);
        Some((*values >> (32 - shift)) as u32)
    }

    /// The value of direction `d` of `slot`.
    #[inline(always)]
    pub(super) fn value(&self, slot: usize, d: usize) -> u32 {
        (self.slots[slot].1 >> (32 * d)) as u32
    }

    /// Doubles the table, keeping its edges and the queue's slots.
    #[cold]
    pub(super) fn grow(&mut self) {
        let old: Vec<_> = self.used[..self.count]
            .iter()
            .map(|&s| self.slots[s as usize])
            .collect();
        let size = 2 * self.slots.len();
        self.slots.clear();
        self.slots.resize(size, (EMPTY, u64::MAX));
        self.used.resize(size, 0);
        self.shift = 64 - size.trailing_zeros();
        for (k, &(key, values)) in old.iter().enumerate() {
            let s = self.find(key);
            self.slots[s] = (key, values);
            self.used[k] = s as u32;
        }
        for q in 0..self.queue.len() {
            let (a, b, _) = self.queue[q];
            let (key, d) = Self::key(a, b);
            // The queued direction a → b is the one across (b → a)'s.
            self.queue[q].2 = Queued::across(self.find(key), 1 - d);
        }
    }
}
