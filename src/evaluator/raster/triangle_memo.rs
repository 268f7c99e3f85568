//! The error totals of triangles already rasterised, by their vertices.
//!
//! The children of one crossover share some of the triangles of the region R that their
//! reused triangles leave uncovered (a seam between two blocks with different levels comes
//! back in other rows of the orthogonal array), and a child scored without its mesh has all
//! of its R triangles rasterised again when its mesh is composed for a mutant. A triangle's
//! totals depend on its three vertices and the height field alone, so a memo of the latest
//! ones spares the raster of each repeat: a probe costs a few dozen instructions, a raster
//! hundreds.

use super::grid_of;
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::exact::predicates::Lattice;
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// A slot nobody uses (no triangle has a vertex `u32::MAX`).
const EMPTY: [u32; 3] = [u32::MAX; 3];

/// Triangles (canonical rotation: smallest grid index first) with their error totals, by open
/// addressing. The slots hold the vertices and an index into the totals, 16 bytes: a probe
/// touches a quarter of a cache line, and the table stays in the first-level cache (with the
/// totals in the slots it would not).
#[derive(Clone, Debug, Default)]
pub(crate) struct TriangleMemo {
    /// The height field the totals are of.
    field: Option<Arc<Heightfield>>,
    slots: Vec<([u32; 3], u32)>,
    /// The totals, in the order the triangles were remembered.
    totals: Vec<ErrorTotals>,
    /// 64 − log2 of the number of slots.
    shift: u32,
}

impl TriangleMemo {
    /// Most triangles remembered: past it the memo starts again (the repeats are among the
    /// latest crossovers', several hundred each; a small table stays in cache).
    pub(crate) const CAPACITY: usize = 1 << 12;

    /// Makes the memo one of `hf`'s totals, forgetting what it holds when that was of another
    /// height field or is past [`CAPACITY`](Self::CAPACITY). With no height field (`None`),
    /// the memo forgets everything and neither knows nor learns any triangle.
    pub(crate) fn prepare(&mut self, hf: Option<&Arc<Heightfield>>) {
        let same = match (&self.field, hf) {
            (Some(f), Some(h)) => Arc::ptr_eq(f, h),
            _ => false,
        };
        if !same || self.totals.len() >= Self::CAPACITY {
            self.clear();
            self.field = hf.cloned();
        }
    }

    /// Forgets every triangle.
    pub(crate) fn clear(&mut self) {
        if !self.totals.is_empty() {
            self.slots.fill((EMPTY, 0));
            self.totals.clear();
        }
    }

    /// The slot of `tri`, or the empty one where it would go.
    #[inline(always)]
    fn find(&self, tri: [u32; 3]) -> usize {
        let mask = self.slots.len() - 1;
        let key = (u64::from(tri[0]) << 32 | u64::from(tri[1])) ^ u64::from(tri[2]).rotate_left(17);
        let mut s = (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> self.shift) as usize;
        loop {
            let k = self.slots[s].0;
            if k == tri || k == EMPTY {
                return s;
            }
            s = (s + 1) & mask;
        }
    }

    /// The totals of `tri`, if known.
    #[inline(always)]
    pub(crate) fn get(&self, tri: [u32; 3]) -> Option<ErrorTotals> {
        if self.totals.is_empty() || self.field.is_none() {
            return None;
        }
        let (k, at) = self.slots[self.find(tri)];
        (k == tri).then(|| self.totals[at as usize])
    }

    /// Remembers the totals of `tri`.
    #[inline(always)]
    pub(crate) fn insert(&mut self, tri: [u32; 3], totals: ErrorTotals) {
        if self.field.is_none() {
            return;
        }
        if 2 * (self.totals.len() + 1) > self.slots.len() {
            self.grow();
        }
        let s = self.find(tri);
        if self.slots[s].0 == tri {
            self.totals[self.slots[s].1 as usize] = totals;
        } else {
            self.slots[s] = (tri, self.totals.len() as u32);
            self.totals.push(totals);
        }
    }

    /// Calls `done(key, totals)` for every `(key, tri)` of `tris` (counter-clockwise, in the
    /// canonical rotation): the totals the memo knows, the others rasterised on `hf` (after
    /// the known ones; every kernel gives the same bits) and remembered. `unknown`: scratch.
    pub(crate) fn sum_triangles<K: Copy>(
        &mut self,
        hf: &Heightfield,
        tris: impl IntoIterator<Item = (K, [u32; 3])>,
        unknown: &mut Vec<(K, [u32; 3])>,
        mut done: impl FnMut(K, ErrorTotals),
    ) {
        unknown.clear();
        for (key, tri) in tris {
            match self.get(tri) {
                Some(known) => done(key, known),
                None => unknown.push((key, tri)),
            }
        }
        let lattice = Lattice::new(hf.width());
        let points = unknown
            .iter()
            .map(|&(key, tri)| ((key, tri), tri.map(|i| lattice.point(i))));
        grid_of(hf).sum_triangles(ErrorUnits::of(hf), points, |(key, tri), totals| {
            self.insert(tri, totals);
            done(key, totals);
        });
    }

    /// Doubles the table (from 256 slots), keeping its triangles.
    #[cold]
    fn grow(&mut self) {
        let old = std::mem::take(&mut self.slots);
        let size = (2 * old.len()).max(256);
        self.slots = vec![(EMPTY, 0); size];
        self.shift = 64 - size.trailing_zeros();
        for (tri, at) in old {
            if tri != EMPTY {
                let s = self.find(tri);
                self.slots[s] = (tri, at);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(z: f64) -> Arc<Heightfield> {
        Arc::new(Heightfield::new(3, 3, vec![z; 9]).unwrap())
    }

    fn totals(k: u64) -> ErrorTotals {
        ErrorTotals {
            sum: k,
            sum_sq: k * k,
            max: k as f64,
        }
    }

    /// As many triangles as the memo holds (so the table grows several times) come back with
    /// their own totals, and unknown ones are not found.
    #[test]
    fn remembers_each_triangle_through_growth() {
        let hf = field(0.0);
        let mut memo = TriangleMemo::default();
        memo.prepare(Some(&hf));
        let tri = |k: u32| [k, k * 7 + 1, k * 13 + 2];
        let most = TriangleMemo::CAPACITY as u32 - 1;
        for k in 0..most {
            memo.insert(tri(k), totals(u64::from(k)));
        }
        for k in 0..most {
            assert_eq!(memo.get(tri(k)), Some(totals(u64::from(k))));
        }
        assert_eq!(memo.get([1, 2, 3]), None);
        // The same field again keeps them.
        memo.prepare(Some(&hf));
        assert_eq!(memo.get(tri(5)), Some(totals(5)));
    }

    /// Totals are of one height field: another one (even with equal heights: the memo cannot
    /// tell), none, or a full memo starts afresh.
    #[test]
    fn forgets_on_another_field_none_or_capacity() {
        let (hf, other) = (field(0.0), field(0.0));
        let mut memo = TriangleMemo::default();
        memo.prepare(Some(&hf));
        memo.insert([0, 1, 4], totals(3));
        memo.prepare(Some(&other));
        assert_eq!(memo.get([0, 1, 4]), None);
        memo.insert([0, 1, 4], totals(3));
        memo.prepare(None);
        assert_eq!(memo.get([0, 1, 4]), None);
        memo.insert([0, 1, 4], totals(3));
        assert_eq!(
            memo.get([0, 1, 4]),
            None,
            "a memo without a field learns nothing"
        );
        memo.prepare(Some(&hf));
        for k in 0..TriangleMemo::CAPACITY as u32 {
            memo.insert([k, k + 1, k + 2], totals(1));
        }
        assert_eq!(memo.get([0, 1, 2]), Some(totals(1)));
        memo.prepare(Some(&hf));
        assert_eq!(memo.get([0, 1, 2]), None);
    }
}
