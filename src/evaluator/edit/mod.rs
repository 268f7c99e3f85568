//! A scored mesh that can be edited: remove and insert kept points, and get the score of the new
//! kept set bit for bit as a fresh [`Evaluator::score`](crate::evaluator::Evaluator::score) would give it.
//!
//! How, and why it is exact:
//! - The triangulation is the canonical Delaunay triangulation of the kept set (unique under the
//!   tie rule of [`predicates`](crate::evaluator::exact::predicates)), so the triangulation reached by local edits is *the same set of
//!   triangles* as the one built from scratch. A removal deletes the vertex's star and fills the
//!   hole with the Delaunay triangles of its boundary
//!   ([`hole_fill`](crate::evaluator::mesh::hole_fill)); an insertion locates the point by a
//!   visibility walk and splits and flips ([`Triangulation::insert_point`](crate::evaluator::Triangulation::insert_point)). Both restore the Delaunay property under the tie rule, so each
//!   intermediate mesh is canonical too.
//! - Every grid point's error comes from the one triangle that owns it ([`raster`](crate::evaluator::raster)),
//!   rasterised with its vertices in a canonical rotation (smallest grid index first), so a
//!   triangle gives the same bits whichever way it was created. The state keeps each triangle's
//!   error totals; a triangle that no edit touched owns the same points with the same totals as
//!   before, and only the touched triangles are rasterised again.
//! - The totals are exact fixed-point integers ([`fixed_point`](crate::evaluator::exact::fixed_point)), so the mesh's score,
//!   their sum over its triangles, is the same in any order.
//!
//! Cost: an edit costs about its walk, its flips or hole fill, and the area of the triangles it
//! changed; a state costs ≈ 5 bytes per grid point plus 48 bytes per triangle, or only the
//! latter while its per-grid-point arrays are lent out ([`MeshState::detach_lookups`]).

mod remove;
mod scratch;

pub(crate) use scratch::EditScratch;
use scratch::REGION_MIN_REMOVALS;

use crate::evaluator::error::EvaluateError;
use crate::evaluator::exact::fixed_point::ErrorTotals;
use crate::evaluator::exact::predicates::Lattice;
use crate::evaluator::mesh::disc_box::DiscBox;
use crate::evaluator::mesh::state::MeshState;
use crate::evaluator::score::Score;
use crate::heightfield::Heightfield;
use std::sync::Arc;

impl MeshState {
    /// Removes the kept points `remove`, then inserts `insert`, and rescores. On error nothing
    /// changes.
    pub(crate) fn edit(
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
        // The kept points' bitset, when up to date, stays so (a bit per changed point).
        let lookup_valid = self.lookup_valid;
        for &i in remove {
            self.mark_kept_bit(i, false);
        }
        for &i in insert {
            self.mark_kept_bit(i, true);
        }
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
        self.lookup_valid = lookup_valid;
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::Evaluator;
    use crate::evaluator::mesh::canonical_form::canonical_set;
    use rand::{RngExt, SeedableRng};

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
