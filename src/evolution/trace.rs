//! What one NSGA-II generation did, phase by phase: the record the teaching view steps through.
//!
//! [`Nsga2`](super::Nsga2) fills a [`GenerationTrace`] while it makes a generation and publishes
//! it when the generation completes ([`Nsga2::last_generation`](super::Nsga2::last_generation)).
//! Recording draws no random numbers and changes nothing the run does, so a traced run and an
//! untraced one are the same run.

use crate::evaluator::Score;
use serde::Serialize;

/// The phases of one NSGA-II generation, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub(crate) enum Phase {
    /// Binary tournaments pick the parents.
    Selection,
    /// Pairs of parents are recombined.
    Crossover,
    /// Bit-flip mutation of every child.
    Mutation,
    /// The children are scored (E, T).
    Evaluation,
    /// Parents and children are sorted into non-dominated fronts.
    Sorting,
    /// Crowding distances within each front.
    Crowding,
    /// The μ best by front, then crowding, survive.
    Survival,
}

impl Phase {
    /// Every phase, in order.
    pub(crate) const ALL: [Phase; 7] = [
        Phase::Selection,
        Phase::Crossover,
        Phase::Mutation,
        Phase::Evaluation,
        Phase::Sorting,
        Phase::Crowding,
        Phase::Survival,
    ];

    /// Name for people.
    pub(crate) fn label(self) -> &'static str {
        match self {
            Phase::Selection => "selection",
            Phase::Crossover => "crossover",
            Phase::Mutation => "mutation",
            Phase::Evaluation => "evaluation",
            Phase::Sorting => "non-dominated sorting",
            Phase::Crowding => "crowding distance",
            Phase::Survival => "survival",
        }
    }

    /// What the phase does, in one line.
    pub(crate) fn explanation(self) -> &'static str {
        match self {
            Phase::Selection => {
                "Binary tournaments: of two random individuals the one in the better front wins, \
                 ties go to the larger crowding distance; each mating needs two winners."
            }
            Phase::Crossover => {
                "With probability p_c a pair is recombined; orthogonal-array crossover scores the \
                 array's rows, estimates each block's effect and also builds the best-levels child."
            }
            Phase::Mutation => {
                "Every free gene of every child flips with probability p_m (1/L by default): \
                 about one grid point added or removed per child."
            }
            Phase::Evaluation => {
                "Each new child is triangulated and scored: E = Σ|z − z̃| over all grid points, \
                 T = its triangle count."
            }
            Phase::Sorting => {
                "Parents and children together are sorted into fronts: F1 is dominated by no one, \
                 F2 only by F1, and so on."
            }
            Phase::Crowding => {
                "Within a front, an individual's crowding distance is the size of the gap between \
                 its neighbours; the ends of a front get infinity."
            }
            Phase::Survival => {
                "Whole fronts survive while they fit in the population; the front that does not \
                 fit keeps its least crowded members."
            }
        }
    }
}

/// One member of a population as the trace keeps it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Member {
    /// Its objectives.
    pub objectives: Score,
    /// Its front (0 = F1) in the population it was ranked in.
    pub rank: usize,
    /// Its crowding distance in that front (infinite at the ends).
    pub crowding: f64,
}

/// One mating of the generation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MatingTrace {
    /// The two tournaments: the population indices drawn in each.
    pub tournaments: [[usize; 2]; 2],
    /// The two winners, the parents (population indices).
    pub parents: [usize; 2],
    /// Whether the pair was recombined (else the children start as copies of the parents).
    pub crossed: bool,
    /// Objectives of the two children before mutation, when known then (the parents' when not
    /// crossed, the chosen rows' for orthogonal-array crossover; unknown for uniform and
    /// two-point crossover, whose children are only scored after mutation).
    pub before_mutation: [Option<Score>; 2],
    /// Evaluations the crossover itself spent (orthogonal-array rows).
    pub crossover_evaluations: usize,
    /// Genes flipped by mutation in each child.
    pub flipped: [usize; 2],
    /// The children's final objectives.
    pub children: [Score; 2],
}

/// What one generation did; see the module doc.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct GenerationTrace {
    /// The generation this trace made (1 for the first one after the initial population).
    pub generation: u64,
    /// The population the generation started from, with its ranks and crowding distances.
    pub parents: Vec<Member>,
    /// The matings, in order.
    pub matings: Vec<MatingTrace>,
    /// The offspring (λ = μ children) in order: the union below is `parents` then these.
    pub offspring: Vec<Score>,
    /// For each member of the union (parents, then offspring): its front and crowding distance
    /// within the union.
    pub union: Vec<Member>,
    /// The union indices that survived, in the order they entered the new population.
    pub survivors: Vec<usize>,
}

impl GenerationTrace {
    /// How many times each parent was picked by a tournament, by population index.
    pub(crate) fn selection_counts(&self) -> Vec<usize> {
        let mut counts = vec![0; self.parents.len()];
        for m in &self.matings {
            for &p in &m.parents {
                if let Some(c) = counts.get_mut(p) {
                    *c += 1;
                }
            }
        }
        counts
    }

    /// True for the union members that survived.
    pub(crate) fn survived(&self) -> Vec<bool> {
        let mut kept = vec![false; self.union.len()];
        for &i in &self.survivors {
            if let Some(k) = kept.get_mut(i) {
                *k = true;
            }
        }
        kept
    }
}
