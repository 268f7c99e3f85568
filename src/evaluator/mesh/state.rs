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
    /// The kept points as a bitset (bit `i` of word `i / 64`), valid only while
    /// `lookup_valid`: filled on demand, then kept up to date by edits and copies (one bit per
    /// grid point, a sixty-fourth of a copy of `kept` per edit).
    pub(crate) kept_bits: Vec<u64>,
    pub(crate) lookup_valid: bool,
    /// The kept points as a summed-area table (`(W + 1) × (H + 1)`, kept points in columns < x
    /// of rows < y at (y, x)), valid only while `sat_valid`: filled on demand with the disc boxes
    /// ([`ensure_discs`](MeshState::ensure_discs)) for the block crossovers this mesh is a parent
    /// of, and dropped by any change (4 bytes per grid point, so only the meshes that need it
    /// hold it).
    pub(crate) kept_sat: Vec<u32>,
    pub(crate) sat_valid: bool,
    /// The sum of every triangle's totals, made with the score: what a mutant's score starts
    /// from, so that scoring it costs the triangles it drops, not all of them.
    pub(crate) all: ErrorTotals,
    /// The [`LARGEST_MAXIMA`] largest per-triangle maxima with their slots, largest first,
    /// made with `all` (zero maxima pad a mesh with fewer nonzero ones): a mutant that drops
    /// the triangle holding the maximum finds the next one here instead of in a pass over the
    /// mesh.
    pub(crate) largest: [(f64, u32); LARGEST_MAXIMA],
    /// Changes whenever the mesh does (a new number from [`next_revision`] at every scoring),
    /// so that what was derived from one mesh ([`PartClasses`](crate::evaluator::PartClasses))
    /// can tell it from later ones; 0 until scored. A copy keeps it: it is the same mesh.
    pub(crate) revision: u64,
}

/// See [`MeshState::largest`].
pub(crate) const LARGEST_MAXIMA: usize = 16;

/// A mesh state's arrays indexed by grid point (kept marks, hints, kept bitset), taken out of a
/// state that is not being edited (`MeshState::detach_lookups`) and lent to one that is
/// (`MeshState::attach_lookups`). A state without them costs memory in proportion to its
/// mesh, not to the grid; a handful of these serve a whole population. Between states the kept
/// marks and bits are all clear (the hints are unspecified), so lending one costs a pass over
/// the mesh, not over the grid.
#[derive(Debug, Default)]
pub struct GridLookups {
    kept: Vec<bool>,
    hint: Vec<u32>,
    kept_bits: Vec<u64>,
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
        self.all = source.all;
        self.largest = source.largest;
        // A copy is about to be edited (that is what the scorer copies for): the disc boxes and
        // the kept points' bitset, which an edit keeps up to date, are copied (cheaper than
        // making them again); the summed-area table, which it does not, is not.
        self.discs_valid = source.discs_valid;
        if source.discs_valid {
            copy_fitted(&mut self.discs, &source.discs);
        }
        self.lookup_valid = source.lookup_valid;
        if source.lookup_valid {
            self.kept_bits.clone_from(&source.kept_bits);
        }
        self.sat_valid = false;
    }
}

impl MeshState {
    /// The score of the state, once scored.
    pub fn score(&self) -> Option<Score> {
        self.score
    }

    /// The triangles (grid-index triples, counter-clockwise), in slot order.
    pub(crate) fn triangles(&self) -> Vec<[u32; 3]> {
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
        self.sat_valid = false;
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

    /// The kept points that share a triangle with kept point `v`, each once, counter-clockwise
    /// around it: a walk around its star from the triangle its hint names. The state must
    /// hold its lookups (`has_lookups`).
    pub(crate) fn neighbours(&self, v: u32) -> Vec<u32> {
        let hf = self.hf.as_ref().expect("a scored state");
        let lattice = Lattice::new(hf.width());
        let t = self.locate(lattice, self.hint[v as usize], lattice.point(v));
        let e = self
            .mesh
            .leaving(t, v)
            .expect("a kept point is a vertex of every triangle whose closed area holds it");
        let mut out = Vec::with_capacity(8);
        for e in self.mesh.fan(e) {
            for u in self.mesh.triangle((e / 3) as usize) {
                if u != v && !out.contains(&u) {
                    out.push(u);
                }
            }
        }
        out
    }

    /// Does this state hold its per-grid-point arrays (a build, an edit or a composition gives
    /// it them; [`detach_lookups`](Self::detach_lookups) takes them away)? Only a state that
    /// holds them can be edited, composed from or tried.
    pub(crate) fn has_lookups(&self) -> bool {
        self.hf
            .as_ref()
            .is_some_and(|hf| self.kept.len() == hf.len())
    }

    /// Takes this scored state's per-grid-point arrays, cleared, leaving a state that costs
    /// memory in proportion to its mesh (also its build scratch and summed-area table go).
    /// [`attach_lookups`](Self::attach_lookups) makes them again. `None` (and no change) when
    /// the state does not hold them or is not scored.
    pub(crate) fn detach_lookups(&mut self) -> Option<GridLookups> {
        if !self.has_lookups() || self.score.is_none() {
            return None;
        }
        // The kept marks are the mesh's vertices: clearing those clears them all.
        for &v in &self.mesh.vertices {
            if v != NONE {
                self.kept[v as usize] = false;
            }
        }
        debug_assert!(!self.kept.contains(&true), "every kept point is a vertex");
        // A sixty-fourth of the grid: cheaper than telling stale bits apart.
        self.kept_bits.fill(0);
        let lookups = GridLookups {
            kept: std::mem::take(&mut self.kept),
            hint: std::mem::take(&mut self.hint),
            kept_bits: std::mem::take(&mut self.kept_bits),
        };
        self.lookup_valid = false;
        self.kept_sat = Vec::new();
        self.sat_valid = false;
        self.mesh.drop_scratch();
        Some(lookups)
    }

    /// Gives a scored state that holds no per-grid-point arrays those of `lookups` (from
    /// [`detach_lookups`](Self::detach_lookups) of any state on the same grid, or
    /// [`GridLookups::default`]), filled from its mesh: its kept marks and bitset, and a hint per
    /// vertex. Costs a pass over the mesh (and over the grid only the first time a set of arrays
    /// is used). Does nothing to a state that holds them or is not scored.
    pub(crate) fn attach_lookups(&mut self, lookups: GridLookups) {
        let Some(n) = self.hf.as_ref().map(|hf| hf.len()) else {
            return;
        };
        if self.has_lookups() || self.score.is_none() {
            return;
        }
        let GridLookups {
            mut kept,
            mut hint,
            mut kept_bits,
        } = lookups;
        if kept.len() != n {
            kept.clear();
            kept.resize(n, false);
            kept_bits.clear();
        }
        hint.resize(n, 0);
        kept_bits.resize(n.div_ceil(64), 0);
        for t in 0..self.mesh.len() {
            for v in self.mesh.triangle(t) {
                kept[v as usize] = true;
                hint[v as usize] = t as u32;
                kept_bits[v as usize / 64] |= 1 << (v % 64);
            }
        }
        (self.kept, self.hint, self.kept_bits) = (kept, hint, kept_bits);
        self.lookup_valid = true;
    }

    /// Fills the disc boxes of this state's triangles, and its kept points' bitset and
    /// summed-area table, if they are stale (a build leaves them so, an edit the table). A
    /// parent is composed from many times, so this is paid once per parent.
    pub fn ensure_discs(&mut self) {
        self.ensure_disc_boxes();
        self.ensure_lookups();
        self.ensure_kept_sat();
    }

    /// Fills the disc boxes of this state's triangles if they are stale: all that
    /// [`Evaluator::compose`](crate::evaluator::Evaluator::compose) needs of a parent.
    pub(crate) fn ensure_disc_boxes(&mut self) {
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
    }

    /// Is this state scored on `hf` with its disc boxes filled, ready to be a composition's
    /// parent?
    pub(crate) fn is_composable_on(&self, hf: &Arc<Heightfield>) -> bool {
        self.hf.as_ref().is_some_and(|h| Arc::ptr_eq(h, hf))
            && self.score.is_some()
            && self.discs_valid
    }

    /// Fills this state's kept points' bitset if it is stale (part of
    /// [`ensure_discs`](Self::ensure_discs), and all that
    /// [`Evaluator::score_mutant`](crate::evaluator::Evaluator::score_mutant) needs). Edits keep
    /// it up to date, so a mesh that is edited and tried in turn pays for it once.
    pub(crate) fn ensure_lookups(&mut self) {
        let Some(hf) = self.hf.clone() else {
            return;
        };
        if !self.lookup_valid && self.has_lookups() {
            let kept = &self.kept[..hf.len()];
            self.kept_bits.clear();
            self.kept_bits.extend(kept.chunks(64).map(|c| {
                c.iter()
                    .enumerate()
                    .fold(0u64, |word, (k, &b)| word | (u64::from(b) << k))
            }));
            self.lookup_valid = true;
        }
    }

    /// Sets or clears bit `i` of the kept points' bitset, when it is up to date.
    pub(crate) fn mark_kept_bit(&mut self, i: u32, kept: bool) {
        if self.lookup_valid {
            let (word, bit) = (i as usize / 64, i % 64);
            if kept {
                self.kept_bits[word] |= 1 << bit;
            } else {
                self.kept_bits[word] &= !(1 << bit);
            }
        }
    }

    /// Fills this state's kept points' summed-area table if it is stale (part of
    /// [`ensure_discs`](Self::ensure_discs), for the block crossovers' part scores).
    fn ensure_kept_sat(&mut self) {
        let Some(hf) = self.hf.clone() else {
            return;
        };
        let (w, h) = (hf.width(), hf.height());
        if !self.sat_valid && self.has_lookups() {
            let kept = &self.kept[..w * h];
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
            self.sat_valid = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::{Changes, Evaluator};
    use rand::{RngExt, SeedableRng};

    /// The kept bitset made afresh from the kept marks.
    fn bits_of(state: &MeshState) -> Vec<u64> {
        let mut fresh = state.clone();
        fresh.lookup_valid = false;
        fresh.ensure_lookups();
        fresh.kept_bits
    }

    /// A state whose per-grid-point arrays were taken away (and others lent back, from another
    /// state) edits, tries and scores exactly as one that kept its own; edits keep the kept
    /// bitset up to date.
    #[test]
    fn lent_lookups_serve_as_the_states_own() {
        let (w, h) = (37usize, 23usize);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let z = (0..w * h).map(|_| rng.random::<f64>() * 10.0).collect();
        let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
        let mut ev = Evaluator::new(hf.clone());
        let draw = |rng: &mut rand_pcg::Pcg64Mcg, p: f64| -> Vec<u32> {
            (0..(w * h) as u32)
                .filter(|_| rng.random::<f64>() < p)
                .collect()
        };
        let (mut own, mut other) = (MeshState::default(), MeshState::default());
        let kept = draw(&mut rng, 0.2);
        ev.score_into(&kept, &mut own).unwrap();
        ev.score_into(&draw(&mut rng, 0.5), &mut other).unwrap();
        own.ensure_lookups();
        let mut lent = own.clone();
        let taken = lent.detach_lookups().expect("a scored state holds them");
        assert!(!lent.has_lookups() && lent.kept.is_empty() && lent.hint.is_empty());
        assert!(taken.kept.iter().all(|&k| !k) && taken.kept_bits.iter().all(|&b| b == 0));
        // Lent the other state's arrays, cleared by taking them.
        lent.attach_lookups(other.detach_lookups().unwrap());
        assert!(lent.has_lookups() && lent.lookup_valid);
        assert_eq!(lent.kept, own.kept);
        assert_eq!(lent.kept_bits, own.kept_bits);
        let corners = hf.corners();
        for round in 0..30 {
            let kept: Vec<u32> = (0..(w * h) as u32).filter(|&i| own.is_kept(i)).collect();
            let remove: Vec<u32> = kept
                .iter()
                .copied()
                .filter(|i| !corners.contains(i) && rng.random::<f64>() < 0.05)
                .collect();
            let insert: Vec<u32> = (0..(w * h) as u32)
                .filter(|&i| !own.is_kept(i) && rng.random::<f64>() < 0.02)
                .collect();
            let changes = Changes {
                removed: &remove,
                inserted: &insert,
            };
            let tried = ev.score_mutant(&own, changes);
            assert_eq!(ev.score_mutant(&lent, changes), tried, "round {round}");
            let a = ev.edit(&mut own, &remove, &insert).unwrap();
            let b = ev.edit(&mut lent, &remove, &insert).unwrap();
            assert_eq!(a, b, "round {round}");
            if let Some(tried) = tried {
                assert_eq!(tried, a, "round {round}");
            }
            assert!(lent.lookup_valid, "an edit keeps the bitset");
            assert_eq!(lent.kept_bits, bits_of(&lent), "round {round}");
            if round % 3 == 0 {
                // Set aside and lent back its own arrays, as a stowed population member.
                let taken = lent.detach_lookups().unwrap();
                lent.attach_lookups(taken);
            }
        }
    }
}
