//! How the scorer picks the way to a chromosome's score, cheapest first: the score of an equal
//! pooled chromosome; for a crossed child, scoring without a mesh from its classified parents;
//! for a mutant of a crossed child or of a pooled chromosome, scoring its changes without a
//! mesh; an edit of the nearest pooled mesh when it is near enough; a composition from both
//! pooled parents; a fresh build. Every way gives the same bits.

use super::Scorer;
use super::pool::Key;
use super::profile::Profile;
use crate::evaluator::{EvaluateError, Score};
use crate::evolution::chromosome::Chromosome;
use crate::evolution::oax::Parentage;

/// The largest Hamming distance, as a fraction of the grid points, at which the scorer edits a
/// pooled mesh rather than building a new one. An edit costs per differing gene, a fresh build
/// per grid point; they cross near 0.7 of the grid (`cargo bench --bench evaluator --
/// incremental`), and 0.5 keeps a margin.
pub(super) const EDIT_LIMIT_PER_POINT: f64 = 0.5;

/// A crossed child is composed from its parents' meshes ([`Scorer::score_crossed`]) only when
/// every pooled chromosome is more than [`COMPOSE_MIN_GENES`] + (T_A + T_B) / this many genes
/// from it (T_A, T_B the parents' triangle counts); nearer, an edit of that one is cheaper.
/// Composing costs per parent triangle, an edit per differing gene (`cargo bench --bench
/// evaluator -- compose`).
pub(super) const COMPOSE_TRIANGLES_PER_GENE: usize = 20;

/// See [`COMPOSE_TRIANGLES_PER_GENE`]: a composition has a fixed cost too, so a child of
/// parents near each other (the weighted-sum GA's) is edited rather than composed.
pub(super) const COMPOSE_MIN_GENES: usize = 100;

/// A crossed child is scored without a mesh ([`Scorer::score_crossed`]) unless a pooled
/// chromosome is within this many genes of it, which is then edited instead.
pub(super) const ROW_EDIT_GENES: usize = 40;

/// A mutant of a crossed child scored without a mesh differs from it in at most this many
/// genes (beyond, the child's mesh is composed and edited). The GA's mutants differ in one or
/// two.
const MUTANT_CHANGES: usize = 8;

/// The base of an edit: a pooled chromosome, or a row of the current crossover (whose mesh is
/// composed first).
#[derive(Clone, Copy, Debug)]
enum Base {
    Pool(usize),
    Row(usize),
}

/// The pool slots of a crossed child's parents A and B, and the genes it takes from B.
type PooledParents<'a> = ([usize; 2], &'a Chromosome);

impl Scorer {
    /// Scores `c`, a crossed child made as `made` says when there is one, by the cheapest way
    /// (see the module doc); one evaluation.
    pub(super) fn score_made(&mut self, c: &Chromosome, made: Option<Parentage<'_>>) -> Score {
        self.evaluations += 1;
        self.tick += 1;
        let parents = self.pooled_parents(made);
        let ones = c.count_ones();
        let profile = Profile::of(c);
        if let Some(score) = self.score_as_row(c, ones, profile, made, parents) {
            return score;
        }
        let limit = self.edit_limit(c, parents);
        let mut nearest = self.nearest(c, ones, &profile, limit + 1);
        if let Some((Base::Pool(i), 0)) = nearest {
            self.pool[i].used = self.tick;
            self.remember(i);
            return self.pool[i].score;
        }
        if made.is_none()
            && let Some(score) = self.score_as_mutant(c, ones, profile, nearest)
        {
            return score;
        }
        if let Some((Base::Row(r), d)) = nearest {
            nearest = self.materialize(r).map(|slot| (Base::Pool(slot), d));
        }
        let base = nearest.map(|(base, _)| match base {
            Base::Pool(i) => i,
            Base::Row(_) => unreachable!("rows are materialised above"),
        });
        // Compose when no base is near enough.
        let parents = parents.filter(|_| base.is_none());
        let slot = self.slot_for(c, ones, profile, made.is_some(), base, parents);
        let composed = parents.and_then(|(ab, from_b)| self.compose_into(slot, ab, from_b, made));
        let score = match composed {
            Some(s) => Ok(s),
            None => self.edit_or_build(c, base, slot),
        };
        // A chromosome has one bit per grid point, and the pooled mesh is the one of the base's
        // genes (corners aside, which both keep), so neither call can fail.
        let score = score.expect("chromosome indices are grid indices");
        self.keys[slot] = Key { ones, profile };
        let entry = &mut self.pool[slot];
        entry.genes.clone_from(c);
        entry.score = score;
        entry.used = self.tick;
        entry.crossed = made.is_some();
        self.remember(slot);
        score
    }

    /// The pool slots of `made`'s parents when both are pooled (and distinct), with the genes
    /// taken from B.
    fn pooled_parents<'a>(&self, made: Option<Parentage<'a>>) -> Option<PooledParents<'a>> {
        made.filter(|_| self.capacity >= 3).and_then(|m| {
            let [a, b] = [self.pooled(m.parents[0])?, self.pooled(m.parents[1])?];
            (a != b).then_some(([a, b], m.from_b))
        })
    }

    /// Scores the crossed child `c` without a mesh when its crossover's parents are pooled and
    /// classified (see [`crossing_row`](Self::crossing_row)), unless a pooled chromosome is so
    /// near that editing it is cheaper (or equal to it); `None` when it is not scored so.
    fn score_as_row(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        made: Option<Parentage<'_>>,
        parents: Option<PooledParents<'_>>,
    ) -> Option<Score> {
        let (m, ([a, b], _)) = (made?, parents?);
        if self
            .nearest(c, ones, &profile, ROW_EDIT_GENES + 1)
            .is_some()
        {
            return None;
        }
        let levels = self.classify(m, [a, b])?;
        self.crossing_row(c, ones, profile, levels)
    }

    /// The largest distance at which a base is worth editing: nearer than where a fresh build,
    /// or composing from pooled `parents`, becomes cheaper; it also cuts the search short.
    fn edit_limit(&self, c: &Chromosome, parents: Option<PooledParents<'_>>) -> usize {
        let limit = (EDIT_LIMIT_PER_POINT * c.len() as f64) as usize;
        match parents {
            Some(([a, b], _)) => {
                let triangles = self.pool[a].score.t + self.pool[b].score.t;
                limit.min(COMPOSE_MIN_GENES + triangles / COMPOSE_TRIANGLES_PER_GENE)
            }
            None => limit,
        }
    }

    /// Scores `c`, a mutant (not a crossed child) whose `nearest` chromosome is a few genes
    /// away, without a mesh, deferring its mesh: a mutant of a crossed child scored without
    /// its mesh, or of a pooled chromosome that it would otherwise copy to edit. `None` when
    /// it is not scored so (a crossed child's mesh is then composed and edited).
    fn score_as_mutant(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        nearest: Option<(Base, usize)>,
    ) -> Option<Score> {
        match nearest? {
            (_, d) if d > MUTANT_CHANGES => None,
            (Base::Row(r), _) => self.mutant_row(c, ones, profile, r),
            (Base::Pool(i), _) if !self.pool[i].crossed => {
                self.mutant_of_pooled(c, ones, profile, i)
            }
            (Base::Pool(_), _) => None,
        }
    }

    /// The nearest chromosome to `c` (`ones` set genes, `profile`) closer than `bound` genes,
    /// and its distance: a pooled one or, when strictly nearer, a child of the current
    /// crossover scored without its mesh. The first of equals among the pooled ones.
    fn nearest(
        &self,
        c: &Chromosome,
        ones: usize,
        profile: &Profile,
        mut bound: usize,
    ) -> Option<(Base, usize)> {
        let mut nearest = None;
        // The distance to a chromosome (its genes, count and profile) when below `bound`: the
        // difference of the counts and of the profiles bound it from below and skip most.
        let below = |genes: &Chromosome, their_ones: usize, theirs: &Profile, bound: usize| {
            if their_ones.abs_diff(ones) >= bound || theirs.distance_below(profile) >= bound {
                return None;
            }
            genes.hamming_below(c, bound)
        };
        // The most recently scored first: a mutant's base is the crossed child scored just
        // before it, and a tight bound early lets the rest of the scan skip or stop early.
        let recent = self.recent.into_iter().filter(|&i| i < self.pool.len());
        for i in recent.chain(0..self.pool.len()) {
            let key = &self.keys[i];
            if let Some(d) = below(&self.pool[i].genes, key.ones, &key.profile, bound) {
                nearest = Some((Base::Pool(i), d));
                bound = d;
                if d == 0 {
                    return nearest;
                }
            }
        }
        for (r, row) in self.rows.iter().enumerate() {
            if let Some(d) = below(&row.genes, row.ones, &row.profile, bound) {
                nearest = Some((Base::Row(r), d));
                bound = d;
            }
        }
        nearest
    }

    /// The pool slot to score `c` into: the base itself when it is a crossed child and `c` is
    /// not (a mutant of it: the crossed child is an intermediate that nothing needs once its
    /// mutant is scored, so its mesh is edited in place instead of copied first); else a new
    /// one while the pool grows, else the least recently used one that is neither the base nor
    /// a parent (the base itself when the pool holds one mesh).
    fn slot_for(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        crossed: bool,
        base: Option<usize>,
        parents: Option<PooledParents<'_>>,
    ) -> usize {
        match base.filter(|&b| !crossed && self.pool[b].crossed) {
            Some(b) => b,
            None => {
                let keep = [base, parents.map(|p| p.0[0]), parents.map(|p| p.0[1])];
                self.free_slot(c, ones, profile, keep)
            }
        }
    }

    /// Composes into pool slot `slot` the mesh of a child of the pooled parents `[a, b]` that
    /// takes `from_b` from B, by the crossover's classification when there is one for these
    /// parents (else by the bitset); `None` when composing refused.
    fn compose_into(
        &mut self,
        slot: usize,
        [a, b]: [usize; 2],
        from_b: &Chromosome,
        made: Option<Parentage<'_>>,
    ) -> Option<Score> {
        self.ready_parents([a, b]);
        let mut state = std::mem::take(&mut self.pool[slot].state);
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        // A failed classification is not `is_for` these parents, so the row falls back to the
        // bitset.
        let by_parts = made
            .filter(|_| self.crossing.is_for(pa, pb))
            .and_then(|m| self.levels_of(m));
        let score = match by_parts {
            Some(levels) => {
                self.evaluator
                    .compose_parts(&mut state, pa, pb, &self.crossing, levels)
            }
            None => self.evaluator.compose(&mut state, pa, pb, from_b.words()),
        };
        self.pool[slot].state = state;
        score
    }

    /// Scores `c` into pool slot `slot` by editing the mesh of pooled `base` (copied first
    /// unless it is the slot), or by a fresh build without a base.
    fn edit_or_build(
        &mut self,
        c: &Chromosome,
        base: Option<usize>,
        slot: usize,
    ) -> Result<Score, EvaluateError> {
        match base {
            Some(b) => {
                let corners = self.evaluator.heightfield().corners();
                (self.pool[b].genes).write_edit(c, &corners, &mut self.removed, &mut self.inserted);
                if b != slot {
                    self.copy_state(b, slot);
                    self.pool[b].used = self.tick;
                }
                self.evaluator
                    .edit(&mut self.pool[slot].state, &self.removed, &self.inserted)
            }
            None => {
                c.write_indices(&mut self.indices);
                self.evaluator
                    .score_into(&self.indices, &mut self.pool[slot].state)
            }
        }
    }
}
