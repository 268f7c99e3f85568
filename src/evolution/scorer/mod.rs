//! The scorer: turns chromosomes into [`Score`]s on one height field, counts the evaluations,
//! and keeps a pool of meshes so that most chromosomes are scored from a near one instead of
//! from scratch.
//!
//! A child mostly resembles chromosomes scored shortly before it: a mutated child differs from
//! its crossed child in a gene or two, an OAX row from a parent or a sibling in a few blocks.
//! The [`Scorer`] therefore keeps the meshes ([`MeshState`](crate::evaluator::MeshState)) of
//! recently used chromosomes in a bounded pool (`pool.rs`), and picks for each chromosome the
//! cheapest way to its score (`path.rs`): the score of an equal pooled chromosome, an edit of
//! the nearest pooled mesh ([`Evaluator::edit`]), a composition from both parents' meshes for a
//! crossed child ([`Evaluator::compose`]), or a fresh build. Every way gives the bits of a
//! fresh [`Evaluator::score`] (the evaluator guarantees it), so the pool changes speed only:
//! every run, front and evaluation count is what scoring every chromosome from scratch gives.
//! A chromosome equal to a pooled one still counts one evaluation: the GA's accounting does not
//! depend on the pool.
//!
//! Most offspring never need a mesh: only those that join the population become parents. So a
//! crossed child is scored without one ([`PartScores`], `crossing.rs`), a mutant of it or of a
//! pooled chromosome too, and their meshes are made only for the offspring that the next
//! [`Scorer::keep_alive`] declares alive (`deferred.rs`).

mod crossing;
mod deferred;
mod path;
mod pool;
mod profile;
#[cfg(test)]
mod tests;

pub(crate) use pool::{POOL_PER_MEMBER, POOL_STATES};

use super::chromosome::Chromosome;
use super::oax::Parentage;
use super::scalarisation::Scalarisation;
use crate::evaluator::{Evaluator, PartClasses, PartScores, Score};
use crate::heightfield::Heightfield;
use crossing::Row;
use deferred::Deferred;
use pool::{Key, Pooled, RECENT};
use std::sync::Arc;

/// Scores chromosomes on one height field and counts every evaluation, reusing the meshes of
/// chromosomes scored before (see the module doc).
pub(crate) struct Scorer {
    evaluator: Evaluator,
    indices: Vec<u32>,
    evaluations: u64,
    /// E₀ and T₀ of [`Scalarisation`].
    normalisers: (f64, f64),
    pool: Vec<Pooled>,
    /// Per pool slot, its chromosome's [`Key`] (`ones` is `usize::MAX` for a slot that nothing
    /// may match).
    keys: Vec<Key>,
    capacity: usize,
    /// The most meshes [`POOL_BYTES`] allows.
    capacity_by_bytes: usize,
    tick: u64,
    removed: Vec<u32>,
    /// The last [`RECENT`] pool slots scored (a ring; `usize::MAX` while unfilled).
    recent: [usize; RECENT],
    recent_at: usize,
    inserted: Vec<u32>,
    /// The blocks of the crossover composed last, as rectangles, and its parents' triangles
    /// classified against them: the rows of a crossover share both, so each row's
    /// composition tests a mask per triangle instead of searching circles.
    crossing_blocks: Vec<[usize; 4]>,
    crossing: PartClasses,
    /// The pool slots of the classified crossover's parents A and B.
    crossing_parents: [usize; 2],
    /// What that crossover's children share, for scoring them without their meshes.
    crossing_scores: PartScores,
    /// The children of that crossover scored without their meshes.
    rows: Vec<Row>,
    /// Offspring scored without their meshes since the last [`keep_alive`](Self::keep_alive),
    /// whose meshes are composed only if they join the population (see [`Deferred`]).
    deferred: Vec<Deferred>,
    /// The classifications the deferred offspring are composed from, and buffers for more.
    retained: Vec<PartClasses>,
    spare: Vec<PartClasses>,
}

impl Scorer {
    /// A scorer for `hf` (the corner-only mesh is scored once for E₀; that is not counted).
    pub(crate) fn new(hf: Arc<Heightfield>) -> Self {
        let mut evaluator = Evaluator::new(hf.clone());
        let e0 = evaluator
            .score(&hf.corners())
            .expect("corner indices are grid indices")
            .e_sum;
        let t0 = hf.full_triangles().max(1) as f64;
        let capacity_by_bytes = pool::capacity_by_bytes(&hf);
        Self {
            evaluator,
            indices: Vec::new(),
            evaluations: 0,
            normalisers: (if e0 > 0.0 { e0 } else { 1.0 }, t0),
            pool: Vec::new(),
            keys: Vec::new(),
            capacity: capacity_by_bytes.min(POOL_STATES),
            capacity_by_bytes,
            tick: 0,
            removed: Vec::new(),
            recent: [usize::MAX; RECENT],
            recent_at: 0,
            inserted: Vec::new(),
            crossing_blocks: Vec::new(),
            crossing: PartClasses::default(),
            crossing_parents: [usize::MAX; 2],
            crossing_scores: PartScores::default(),
            rows: Vec::new(),
            deferred: Vec::new(),
            retained: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// Evaluates `c` (one evaluation). The result is exactly [`Evaluator::score`]'s for `c`'s
    /// kept set, whether it was built from scratch or edited from a pooled mesh.
    pub(crate) fn score(&mut self, c: &Chromosome) -> Score {
        self.score_made(c, None)
    }

    /// [`score`](Self::score) for a child of a crossover made as `made` says: when both
    /// parents' meshes are in the pool and no pooled chromosome is near the child (see
    /// [`COMPOSE_TRIANGLES_PER_GENE`]), its mesh is composed from theirs
    /// ([`Evaluator::compose`]). The same score, bit for bit, either way.
    pub(crate) fn score_crossed(&mut self, c: &Chromosome, made: Parentage<'_>) -> Score {
        self.score_made(c, Some(made))
    }

    /// Tells the scorer that `c`, scored as a crossed child, goes on unchanged (a mutation that
    /// flipped no gene): it may become a parent, so its mesh is kept like the other offspring's.
    /// Spends no evaluation.
    pub(crate) fn promote(&mut self, c: &Chromosome) {
        if let Some(i) = self.pooled(c) {
            self.pool[i].crossed = false;
            self.pool[i].used = self.tick;
        } else if let Some(r) = self.rows.iter().position(|r| r.genes == *c) {
            let row = &self.rows[r];
            let (ones, profile, score) = (row.ones, row.profile, row.score);
            self.defer(c, ones, profile, score, r, false);
        }
    }

    /// Tells the scorer which chromosomes make up the GA's population now: their meshes are
    /// replaced only after every other one, so that the parents of the coming crossovers stay
    /// pooled to compose from. Spends no evaluation.
    pub(crate) fn keep_alive<'a>(&mut self, population: impl IntoIterator<Item = &'a Chromosome>) {
        // The new population joins the old one first, so that composing its deferred members
        // replaces neither (the old one holds their parents); then the old one is let go.
        let members: Vec<&Chromosome> = population.into_iter().collect();
        // The pool never shrinks: its meshes stay where they are.
        let wanted = (POOL_PER_MEMBER * members.len()).min(self.capacity_by_bytes);
        self.capacity = self.capacity.max(wanted);
        let mut pooled: Vec<Option<usize>> = members.iter().map(|c| self.pooled(c)).collect();
        for i in pooled.iter().flatten() {
            self.pool[*i].alive = true;
        }
        if !self.deferred.is_empty() {
            for (c, at) in members.iter().zip(&mut pooled) {
                if at.is_some() {
                    continue;
                }
                if let Some(d) = self.deferred.iter().position(|d| d.genes == **c) {
                    *at = self.compose_deferred(d);
                }
            }
            self.drop_deferred();
        }
        for p in &mut self.pool {
            p.alive = false;
        }
        for i in pooled.into_iter().flatten() {
            self.pool[i].alive = true;
        }
    }

    /// Evaluations so far.
    pub(crate) fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The normalised weighted sum with weight `w` for this height field.
    pub(crate) fn scalarisation(&self, w: f64) -> Scalarisation {
        Scalarisation {
            w,
            e0: self.normalisers.0,
            t0: self.normalisers.1,
        }
    }

    /// The height field.
    pub(crate) fn heightfield(&self) -> &Arc<Heightfield> {
        self.evaluator.heightfield()
    }
}
