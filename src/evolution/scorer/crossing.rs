//! The current crossover: its parents' triangles classified against its blocks once for all
//! its rows ([`PartClasses`]), and its children scored without their meshes
//! ([`PartScores`](crate::evaluator::PartScores)),
//! whose meshes are composed only when a mutant is to be edited from one.

use super::Scorer;
use super::deferred::{ClassesAt, Recipe};
use super::pool::Key;
use super::profile::Profile;
use crate::evaluator::{Crossing, PartClasses, Score};
use crate::evolution::chromosome::Chromosome;
use crate::evolution::oax::Parentage;

/// A child of the current crossover scored without its mesh ([`Scorer::crossing_row`]).
#[derive(Clone, Debug)]
pub(super) struct Row {
    pub(super) genes: Chromosome,
    pub(super) ones: usize,
    pub(super) profile: Profile,
    /// Bit k: block k from parent B.
    pub(super) levels: u32,
    pub(super) score: Score,
}

impl Scorer {
    /// The levels of `made`'s blocks as a mask (bit k: block k from B).
    pub(super) fn levels_of(&self, made: Parentage<'_>) -> Option<u32> {
        (made.blocks.len() <= PartClasses::MAX_PARTS).then(|| {
            (made.levels.iter().enumerate())
                .fold(0u32, |acc, (k, &l)| acc | (u32::from(l & 1) << k))
        })
    }

    /// Readies pooled parents `[a, b]` to compose or classify from (their disc boxes and
    /// lookups), and marks them used now.
    pub(super) fn ready_parents(&mut self, parents: [usize; 2]) {
        for p in parents {
            self.pool[p].state.ensure_discs();
            self.pool[p].used = self.tick;
        }
    }

    /// Makes sure the current crossover's classification is for `made`'s blocks and the pooled
    /// parents `[a, b]` (making it at the crossover's first row), and returns `made`'s levels;
    /// `None` when it cannot be made.
    pub(super) fn classify(&mut self, made: Parentage<'_>, [a, b]: [usize; 2]) -> Option<u32> {
        let levels = self.levels_of(made)?;
        self.ready_parents([a, b]);
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        let rects = made.blocks.iter().map(|b| [b.x0, b.y0, b.x1, b.y1]);
        if !self.crossing_blocks.iter().copied().eq(rects.clone()) || !self.crossing.is_for(pa, pb)
        {
            self.crossing_blocks.clear();
            self.crossing_blocks.extend(rects);
            let hf = self.evaluator.heightfield().clone();
            self.crossing.reset(&hf, pa, pb, &self.crossing_blocks);
            self.rows.clear();
        }
        self.crossing_parents = [a, b];
        self.crossing.is_for(pa, pb).then_some(levels)
    }

    /// Scores the child `c` with `levels` of the current crossover without building its mesh
    /// ([`Evaluator::score_parts`](crate::evaluator::Evaluator::score_parts)) and remembers it
    /// among the crossover's rows, to compose its mesh should a mutant need it
    /// ([`materialize`](Self::materialize)). `None` when a guard refuses (the child is then
    /// scored another way).
    pub(super) fn crossing_row(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        levels: u32,
    ) -> Option<Score> {
        let [a, b] = self.crossing_parents;
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        let crossing = Crossing {
            hf: self.evaluator.heightfield(),
            parents: [pa, pb],
            classes: &self.crossing,
        };
        if !self.crossing_scores.is_for(crossing) && !self.crossing_scores.prepare(crossing) {
            return None;
        }
        let score = self.evaluator.score_parts(
            pa,
            pb,
            &self.crossing,
            &mut self.crossing_scores,
            levels,
        )?;
        self.rows.push(Row {
            genes: c.clone(),
            ones,
            profile,
            levels,
            score,
        });
        Some(score)
    }

    /// Composes the mesh of the current crossover's row `r` into a pool slot, as an intermediate
    /// (replaced early), and returns the slot; `None` when its parents changed or composing
    /// refused.
    pub(super) fn materialize(&mut self, r: usize) -> Option<usize> {
        let row = self.rows[r].clone();
        let recipe = Recipe {
            parents: self.crossing_parents,
            classes: ClassesAt::Crossing,
            levels: row.levels,
            changed_as: None,
        };
        let key = Key {
            ones: row.ones,
            profile: row.profile,
        };
        self.compose_pooled(row.genes, key, row.score, recipe, true)
    }
}
