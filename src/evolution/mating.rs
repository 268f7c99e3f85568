//! One mating, shared by NSGA-II and the weighted-sum GA: crossover (with the crossover
//! probability) of two parents into two children, bit-flip mutation of both, and evaluation of
//! whatever changed.
//!
//! A mating is made one evaluation at a time, so that a browser frame never has to wait for a
//! whole orthogonal-array crossover: [`PendingMating::start`] draws the crossover's random
//! choices, then each [`PendingMating::advance`] makes one child (an OAX row, the best-levels
//! child, or one mutated offspring) and spends at most one evaluation. The random draws happen
//! in the same order as when the mating ran in one go (evaluations draw nothing), so the
//! result does not depend on how the work is sliced.

use super::chromosome::Chromosome;
use super::oax::{self, OaxInProgress, OaxRecord};
use super::operators::{self, CrossoverKind};
use super::params::GaParams;
use super::scalarisation::Scalarisation;
use super::scorer::Scorer;
use crate::evaluator::Score;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;

/// What a mating step needs besides its own state.
pub(crate) struct MatingContext<'a> {
    /// Bit-flip probability per free gene.
    pub mutation: f64,
    pub rng: &'a mut Pcg64Mcg,
    pub scorer: &'a mut Scorer,
}

/// A child before its mutation: its genes, and its objectives when they are already known.
type Crossed = (Chromosome, Option<Score>);

enum Stage {
    /// The orthogonal-array crossover is making its children.
    Oax(Box<OaxInProgress>),
    /// The two crossed children are mutated and evaluated in order; `None` once done.
    Mutation { crossed: [Option<Crossed>; 2] },
}

/// A mating in progress; see the module doc.
pub(crate) struct PendingMating {
    /// The scalar fitness OAX's factor analysis minimises.
    scalar: Scalarisation,
    stage: Stage,
    /// The offspring made so far (mutated and evaluated), in order.
    offspring: Vec<(Chromosome, Score)>,
    /// What the trace reports about this mating (see [`super::trace::MatingTrace`]).
    pub(crate) crossed: bool,
    pub(crate) parents: [usize; 2],
    pub(crate) before_mutation: [Option<Score>; 2],
    pub(crate) crossover_evaluations: usize,
    pub(crate) flipped: [usize; 2],
}

impl PendingMating {
    /// Starts a mating of `a` and `b`: draws whether to cross them and, for uniform and
    /// two-point crossover, the children themselves; for OAX, its spatial blocks. Spends no
    /// evaluation.
    pub(super) fn start(
        params: &GaParams,
        scalar: Scalarisation,
        a: (&Chromosome, Score),
        b: (&Chromosome, Score),
        scorer: &Scorer,
        rng: &mut Pcg64Mcg,
    ) -> Self {
        let hf = scorer.heightfield();
        let mutation = |crossed: [Crossed; 2]| Stage::Mutation {
            crossed: crossed.map(Some),
        };
        let crossed = rng.random::<f64>() < params.crossover_probability;
        let stage = if crossed {
            match params.crossover {
                CrossoverKind::Oax => {
                    let blocks = oax::spatial_blocks(hf.width(), hf.height(), params.factors, rng);
                    Stage::Oax(Box::new(OaxInProgress::new(
                        a,
                        b,
                        hf.width(),
                        blocks,
                        scalar.w,
                    )))
                }
                CrossoverKind::Uniform => {
                    mutation(operators::uniform(a.0, b.0, rng).map(|c| (c, None)))
                }
                CrossoverKind::TwoPoint => {
                    mutation(operators::two_point(a.0, b.0, rng).map(|c| (c, None)))
                }
            }
        } else {
            mutation([(a.0.clone(), Some(a.1)), (b.0.clone(), Some(b.1))])
        };
        let before_mutation = match &stage {
            Stage::Mutation { crossed } => crossed
                .each_ref()
                .map(|c| c.as_ref().and_then(|(_, known)| *known)),
            Stage::Oax(_) => [None, None],
        };
        Self {
            scalar,
            stage,
            offspring: Vec::with_capacity(2),
            crossed,
            parents: [0, 0],
            before_mutation,
            crossover_evaluations: 0,
            flipped: [0, 0],
        }
    }

    /// Makes the next child, spending at most one evaluation. `seen` is called on every
    /// chromosome evaluated (OAX rows included), in order; when the OAX crossover completes,
    /// its record goes into `record`. Returns the two evaluated offspring when this step
    /// completes the mating, else `None`.
    pub(super) fn advance(
        &mut self,
        ctx: MatingContext<'_>,
        seen: &mut impl FnMut(&Chromosome, &Score),
        record: &mut Option<OaxRecord>,
    ) -> Option<[(Chromosome, Score); 2]> {
        let MatingContext {
            mutation,
            rng,
            scorer,
        } = ctx;
        let corners = scorer.heightfield().corners();
        let mut score = |c: &Chromosome| {
            let o = scorer.score(c);
            seen(c, &o);
            o
        };
        match &mut self.stage {
            Stage::Oax(crossover) => {
                let scalar = self.scalar;
                let mut score_crossed = |c: &Chromosome, made: oax::Parentage<'_>| {
                    let o = scorer.score_crossed(c, made);
                    seen(c, &o);
                    o
                };
                crossover.next_child(&mut score_crossed, &|o| scalar.value(o));
                if crossover.is_complete() {
                    let placeholder = Stage::Mutation {
                        crossed: [None, None],
                    };
                    let Stage::Oax(crossover) = std::mem::replace(&mut self.stage, placeholder)
                    else {
                        unreachable!("the stage was OAX")
                    };
                    let r = crossover.finish();
                    let pick = |i: usize| {
                        let c = r.child(i);
                        Some((c.genes.clone(), Some(c.objectives)))
                    };
                    self.stage = Stage::Mutation {
                        crossed: [pick(r.chosen[0]), pick(r.chosen[1])],
                    };
                    self.before_mutation = r.chosen.map(|i| Some(r.child(i).objectives));
                    self.crossover_evaluations = r.evaluations();
                    *record = Some(r);
                }
                None
            }
            Stage::Mutation { crossed } => {
                let slot = crossed
                    .iter_mut()
                    .find(|c| c.is_some())
                    .expect("a pending mating has a child left to mutate");
                let (mut genes, known) = slot.take().expect("found as present");
                let flipped = operators::mutate(&mut genes, &corners, mutation, rng);
                self.flipped[self.offspring.len().min(1)] = flipped;
                let objectives = match known {
                    Some(o) if flipped == 0 => {
                        scorer.promote(&genes);
                        o
                    }
                    _ => score(&genes),
                };
                self.offspring.push((genes, objectives));
                if self.offspring.len() < 2 {
                    return None;
                }
                let second = self.offspring.pop().expect("two offspring");
                let first = self.offspring.pop().expect("two offspring");
                Some([first, second])
            }
        }
    }
}
