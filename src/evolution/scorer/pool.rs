//! The scorer's pool of meshes: its slots, their keys for the search, and which slot a new mesh
//! replaces.
//!
//! Replacement is least recently used, except that crossed children go first once there are
//! [`CROSSED_POOLED`] of them (they are intermediates, bases for a mutant at most) and the GA's
//! current population last ([`Scorer::keep_alive`]), as it holds the parents of the coming
//! crossovers.

use super::Scorer;
use super::profile::Profile;
use crate::evaluator::{MeshState, Score};
use crate::evolution::chromosome::Chromosome;
use crate::heightfield::Heightfield;

/// How many crossed children the pool keeps before it replaces them ahead of other
/// chromosomes: a crossover's rows (at most 8 with L8, plus the best-levels child) and some
/// slack, so that the children a mutant is edited from stay pooled.
pub(super) const CROSSED_POOLED: usize = 24;

/// How many of the most recently scored chromosomes the scorer compares with first.
pub(super) const RECENT: usize = 16;

/// Most meshes the scorer keeps until the GA declares a population larger than half of it
/// ([`Scorer::keep_alive`]), and then [`POOL_PER_MEMBER`] per member. The pool holds the
/// population, which the GAs declare alive so that both parents of every crossover are pooled
/// to compose from, the offspring that join it (their meshes are composed while the old
/// population, which holds their parents, is still pooled), and the bases of a crossover's
/// edits. Fewer meshes make composing the new members replace their parents; more only touch
/// more memory.
pub(crate) const POOL_STATES: usize = 200;

/// Meshes the pool holds per member of the declared population, when that is more than
/// [`POOL_STATES`]: the old and the new population (see [`POOL_STATES`]).
pub(crate) const POOL_PER_MEMBER: usize = 2;

/// The most memory the pool's meshes may take, whatever the population.
pub(super) const POOL_BYTES: usize = 160 << 20;

/// The most meshes of `hf` that [`POOL_BYTES`] holds.
pub(super) fn capacity_by_bytes(hf: &Heightfield) -> usize {
    // A mesh state: per point an error (8 bytes), a hint (4), a kept mark (1) and a gene bit;
    // per triangle (at most 2 per point) 6 half-edge words of 4 bytes and a disc box of 8.
    let state_bytes = hf.len() * (8 + 4 + 1 + 2 * (24 + 8)) + hf.len() / 8;
    (POOL_BYTES / state_bytes.max(1)).max(1)
}

/// A scored chromosome with its mesh, in the scorer's pool.
pub(super) struct Pooled {
    pub(super) genes: Chromosome,
    pub(super) state: MeshState,
    pub(super) score: Score,
    /// When it was last scored or used as a base (a tick of the scorer), for replacement.
    pub(super) used: u64,
    /// Scored as a crossed child ([`Scorer::score_crossed`]): an intermediate that is a base
    /// for its mutant at most, replaced before the chromosomes that may become parents.
    pub(super) crossed: bool,
    /// In the GA's current population ([`Scorer::keep_alive`]): a parent of the coming
    /// crossovers, replaced only after every other chromosome.
    pub(super) alive: bool,
}

/// What the scorer's search reads first of a pooled chromosome: its number of set genes and
/// its [`Profile`], kept apart from the rest (`Scorer::keys`) so that the search, which skips
/// most of the pool on them, reads them contiguously.
#[derive(Clone, Copy, Debug)]
pub(super) struct Key {
    pub(super) ones: usize,
    pub(super) profile: Profile,
}

impl Scorer {
    /// A pool slot to score `c` into: a new one while the pool grows, else the least recently
    /// used one not in `keep` (crossed children first once there are [`CROSSED_POOLED`] of
    /// them, the GA's population last).
    pub(super) fn free_slot(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        keep: [Option<usize>; 3],
    ) -> usize {
        if self.pool.len() < self.capacity {
            self.keys.push(Key { ones, profile });
            self.pool.push(Pooled {
                genes: c.clone(),
                state: MeshState::default(),
                score: Score {
                    e_sum: 0.0,
                    e_max: 0.0,
                    rms: 0.0,
                    t: 0,
                },
                used: 0,
                crossed: false,
                alive: false,
            });
            return self.pool.len() - 1;
        }
        // Crossed children are replaced first once there are CROSSED_POOLED of them: the
        // parents of later crossovers are among the others, and composing needs both.
        let crossed = self.pool.iter().filter(|p| p.crossed).count();
        (0..self.pool.len())
            .filter(|&i| !keep.contains(&Some(i)) || self.pool.len() == 1)
            .min_by_key(|&i| {
                let p = &self.pool[i];
                (p.alive, crossed < CROSSED_POOLED || !p.crossed, p.used)
            })
            .expect("the pool is not empty")
    }

    /// Makes pool slot `slot`, whose mesh has just been made (`made`) for `genes` (with `key`,
    /// scored `score`), hold them, as a crossed child (`crossed`, an intermediate) or an
    /// offspring that joins the population (alive), and returns it. When the mesh could not be
    /// made, the slot's mesh is unscored: nothing may match it, and `None`.
    pub(super) fn settle(
        &mut self,
        slot: usize,
        made: bool,
        genes: Chromosome,
        key: Key,
        score: Score,
        crossed: bool,
    ) -> Option<usize> {
        if !made {
            self.pool[slot].genes = Chromosome::empty(0);
            self.keys[slot].ones = usize::MAX;
            return None;
        }
        self.keys[slot] = key;
        let entry = &mut self.pool[slot];
        entry.genes = genes;
        entry.score = score;
        entry.used = self.tick;
        entry.crossed = crossed;
        entry.alive = !crossed;
        Some(slot)
    }

    /// Puts pool slot `i` among the recently scored ones.
    pub(super) fn remember(&mut self, i: usize) {
        self.recent[self.recent_at] = i;
        self.recent_at = (self.recent_at + 1) % RECENT;
    }

    /// Copies the mesh of pool slot `from` into slot `to` (another one), reusing its buffers.
    pub(super) fn copy_state(&mut self, from: usize, to: usize) {
        let (from, to) = if from < to {
            let (lo, hi) = self.pool.split_at_mut(to);
            (&lo[from], &mut hi[0])
        } else {
            let (lo, hi) = self.pool.split_at_mut(from);
            (&hi[0], &mut lo[to])
        };
        to.state.clone_from(&from.state);
    }

    /// The pool slot holding exactly `c`, if any.
    pub(super) fn pooled(&self, c: &Chromosome) -> Option<usize> {
        let ones = c.count_ones();
        self.pool
            .iter()
            .zip(&self.keys)
            .position(|(p, key)| key.ones == ones && p.genes == *c)
    }
}
