//! Offspring scored without their meshes, whose meshes are made only if they join the
//! population.
//!
//! Most offspring die at the next survival, so a crossed child that goes on unchanged, or a
//! mutant scored without a mesh, is remembered with what its mesh is made from; the next
//! [`Scorer::keep_alive`] composes (or edits) the meshes of those that joined the population,
//! while their parents, the old population, are still pooled.

use super::Scorer;
use super::pool::Key;
use super::profile::Profile;
use crate::evaluator::{Changes, Score};
use crate::evolution::chromosome::Chromosome;

/// Most offspring deferred at once: beyond, a GA that declares no population
/// ([`Scorer::keep_alive`]) would keep every classification; they are then dropped (their
/// offspring are scored like any chromosome should they come back).
const MAX_DEFERRED: usize = 1024;

/// An offspring that goes on without its mesh: a crossed child that no mutation changed, or a
/// mutant of one or of a pooled chromosome, scored without a mesh
/// ([`PartScores::score_changed`](crate::evaluator::PartScores::score_changed),
/// [`Evaluator::score_mutant`](crate::evaluator::Evaluator::score_mutant)).
#[derive(Clone, Debug)]
pub(super) struct Deferred {
    pub(super) genes: Chromosome,
    ones: usize,
    profile: Profile,
    score: Score,
    origin: Origin,
    /// What its mutation changed in the crossed child or the base (nothing for a crossed
    /// child that went on unchanged).
    removed: Vec<u32>,
    inserted: Vec<u32>,
}

/// What a deferred offspring's mesh is made from.
#[derive(Clone, Debug)]
enum Origin {
    /// A crossed child with `levels` (bit k: block k from parent B) of the parents in pool
    /// slots `parents`, whose classification is `retained[classes]`.
    Crossed {
        classes: usize,
        parents: [usize; 2],
        levels: u32,
    },
    /// A pooled chromosome, edited (found by its genes when the mesh is made).
    Edited { base: Chromosome },
}

/// Where the classification of a mesh to compose is: the current crossover's, or one retained
/// for deferred offspring (`Scorer::retained`).
#[derive(Clone, Copy, Debug)]
pub(super) enum ClassesAt {
    Crossing,
    Retained(usize),
}

/// How to compose a mesh from pooled parents ([`Scorer::compose_pooled`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Recipe {
    /// The pool slots of parents A and B.
    pub(super) parents: [usize; 2],
    pub(super) classes: ClassesAt,
    /// Bit k: block k from parent B.
    pub(super) levels: u32,
    /// The deferred offspring whose changes are then made (none for a crossed child).
    pub(super) changed_as: Option<usize>,
}

impl Scorer {
    /// Scores `c` (`ones` set genes, `profile`), a mutant of the current crossover's row `r`,
    /// without a mesh, and defers its mesh; `None` when the mutant cannot be scored so.
    pub(super) fn mutant_row(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        r: usize,
    ) -> Option<Score> {
        let [a, b] = self.crossing_parents;
        if a >= self.pool.len() || b >= self.pool.len() {
            return None;
        }
        let row = &self.rows[r];
        let corners = self.evaluator.heightfield().corners();
        (row.genes).write_edit(c, &corners, &mut self.removed, &mut self.inserted);
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        let changes = Changes {
            removed: &self.removed,
            inserted: &self.inserted,
        };
        let score = self.evaluator.score_parts_changed(
            pa,
            pb,
            &self.crossing,
            &mut self.crossing_scores,
            row.levels,
            changes,
        )?;
        self.defer(c, ones, profile, score, r, true);
        Some(score)
    }

    /// Defers the mesh of `c` (`ones` set genes, `profile`, scored `score`): the current
    /// crossover's row `r`, changed by `self.removed` and `self.inserted` when `changed` (see
    /// [`Deferred`]), retaining the crossover's classification for it.
    pub(super) fn defer(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        score: Score,
        r: usize,
        changed: bool,
    ) {
        if self.deferred.len() >= MAX_DEFERRED {
            self.drop_deferred();
        }
        let retained = self
            .retained
            .last()
            .is_some_and(|k| k.id() == self.crossing.id());
        if !retained {
            let mut copy = self.spare.pop().unwrap_or_default();
            copy.clone_from(&self.crossing);
            self.retained.push(copy);
        }
        let (removed, inserted) = match changed {
            true => (self.removed.clone(), self.inserted.clone()),
            false => (Vec::new(), Vec::new()),
        };
        self.deferred.push(Deferred {
            genes: c.clone(),
            ones,
            profile,
            score,
            origin: Origin::Crossed {
                classes: self.retained.len() - 1,
                parents: self.crossing_parents,
                levels: self.rows[r].levels,
            },
            removed,
            inserted,
        });
    }

    /// Scores `c` (`ones` set genes, `profile`), a mutant of pooled chromosome `i` (not a
    /// crossed child, whose mesh is edited in place instead), without a copy of its mesh
    /// ([`Evaluator::score_mutant`](crate::evaluator::Evaluator::score_mutant)), and defers the
    /// mutant's mesh; `None` when it cannot be scored so.
    pub(super) fn mutant_of_pooled(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        i: usize,
    ) -> Option<Score> {
        let base = &mut self.pool[i];
        let corners = self.evaluator.heightfield().corners();
        (base.genes).write_edit(c, &corners, &mut self.removed, &mut self.inserted);
        base.state.ensure_lookups();
        let changes = Changes {
            removed: &self.removed,
            inserted: &self.inserted,
        };
        let score = self.evaluator.score_mutant(&base.state, changes)?;
        base.used = self.tick;
        if self.deferred.len() >= MAX_DEFERRED {
            self.drop_deferred();
        }
        self.deferred.push(Deferred {
            genes: c.clone(),
            ones,
            profile,
            score,
            origin: Origin::Edited {
                base: self.pool[i].genes.clone(),
            },
            removed: self.removed.clone(),
            inserted: self.inserted.clone(),
        });
        Some(score)
    }

    /// Forgets the deferred offspring, keeping their classifications' buffers.
    pub(super) fn drop_deferred(&mut self) {
        self.deferred.clear();
        self.spare.append(&mut self.retained);
    }

    /// Makes the mesh of deferred offspring `d` in a pool slot, alive, and returns the slot
    /// (see [`compose_pooled`](Self::compose_pooled)); `None` when what it is made from is no
    /// longer pooled or composing refused (it then stays unpooled).
    pub(super) fn compose_deferred(&mut self, d: usize) -> Option<usize> {
        let (ones, profile, score) = {
            let d = &self.deferred[d];
            (d.ones, d.profile, d.score)
        };
        let genes = std::mem::replace(&mut self.deferred[d].genes, Chromosome::empty(0));
        let key = Key { ones, profile };
        let base = match &self.deferred[d].origin {
            &Origin::Crossed {
                classes,
                parents,
                levels,
            } => {
                let recipe = Recipe {
                    parents,
                    classes: ClassesAt::Retained(classes),
                    levels,
                    changed_as: Some(d),
                };
                return self.compose_pooled(genes, key, score, recipe, false);
            }
            Origin::Edited { base } => self.pooled(base)?,
        };
        let slot = self.free_slot(&genes, ones, profile, [Some(base), None, None]);
        self.copy_state(base, slot);
        let Deferred {
            removed, inserted, ..
        } = &self.deferred[d];
        let state = &mut self.pool[slot].state;
        let made = self.evaluator.edit(state, removed, inserted).ok();
        debug_assert!(made.is_none_or(|s| (s.e_sum, s.t) == (score.e_sum, score.t)));
        self.settle(slot, made.is_some(), genes, key, score, false)
    }

    /// Composes the mesh of `genes` (with `key`, scored `score`) as `recipe` says into a pool
    /// slot that is neither alive nor one of its parents, and returns the slot: a crossed child
    /// (`crossed`, an intermediate replaced early, and among the recently scored) or an
    /// offspring that joins the population (alive). `None` when its parents changed or
    /// composing refused (it then stays unpooled).
    pub(super) fn compose_pooled(
        &mut self,
        genes: Chromosome,
        key: Key,
        score: Score,
        recipe: Recipe,
        crossed: bool,
    ) -> Option<usize> {
        let [a, b] = recipe.parents;
        if a >= self.pool.len() || b >= self.pool.len() {
            return None;
        }
        let slot = self.free_slot(&genes, key.ones, key.profile, [Some(a), Some(b), None]);
        let mut state = std::mem::take(&mut self.pool[slot].state);
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        let classes = match recipe.classes {
            ClassesAt::Crossing => &self.crossing,
            ClassesAt::Retained(k) => &self.retained[k],
        };
        let mut made = classes
            .is_for(pa, pb)
            .then(|| {
                self.evaluator
                    .compose_parts(&mut state, pa, pb, classes, recipe.levels)
            })
            .flatten();
        if let Some(d) = recipe.changed_as.map(|d| &self.deferred[d])
            && made.is_some()
            && !(d.removed.is_empty() && d.inserted.is_empty())
        {
            made = self
                .evaluator
                .edit(&mut state, &d.removed, &d.inserted)
                .ok();
        }
        debug_assert!(made.is_none_or(|s| (s.e_sum, s.t) == (score.e_sum, score.t)));
        self.pool[slot].state = state;
        let slot = self.settle(slot, made.is_some(), genes, key, score, crossed)?;
        if crossed {
            // About to be a mutant's base.
            self.remember(slot);
        }
        Some(slot)
    }
}
