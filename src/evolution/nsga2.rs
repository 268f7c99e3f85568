//! NSGA-II (Deb et al. 2002) on (E_sum, T) with orthogonal-array crossover.
//!
//! - Initial population: μ random individuals with log-spaced densities
//!   ([`operators::initial_density`]), unless greedy seeding is on (below).
//! - Each generation makes λ = μ offspring: two parents by binary tournament on (rank, then
//!   larger crowding distance), crossover with probability p_c, bit-flip mutation, evaluation.
//! - Elitist (μ + λ) survival: the union is sorted into non-dominated fronts, whole fronts are
//!   kept while they fit, and the last one is cut by decreasing crowding distance. Rank and
//!   crowding are then recomputed on the survivors for the next tournaments.
//! - The archive ([`Optimizer::front`]) receives *every* evaluated chromosome, OAX rows
//!   included, so it is the front of everything seen.
//!
//! OAX's factor analysis needs a scalar fitness. Here it is the normalised weighted sum
//! F = w·E/E₀ + (1 − w)·T/T₀ ([`Scalarisation`](super::scalarisation::Scalarisation)) with a fresh random w ~ U(0, 1) per crossover.
//! Why: the rank of a child among 8 siblings says little (most of them are mutually
//! non-dominated, so ranks tie), and ranking against the whole population would make a
//! crossover's outcome depend on the rest of the population. A random weight asks each
//! crossover to push its two parents in one direction of the front, and over many crossovers
//! every direction is asked for; the normalisation keeps both terms on [0, 1]. Weighted sums
//! cannot reach non-convex parts of a front, but here the scalar only steers recombination:
//! survival is NSGA-II's, and the archive keeps every non-dominated child.
//!
//! Unit of work ([`crate::optimizer`]): one evaluation. A unit creates one initial individual,
//! or makes the next child of the mating in progress: one OAX row, the best-levels child, or
//! one mutated offspring (see `evolution::mating`). A child whose objectives are already known
//! costs no evaluation and its unit does no work beyond bookkeeping; the same holds for starting
//! a mating (two tournaments, the weight and the crossover's random choices, drawn at its first
//! unit) and for the survival step (run by the unit that completes the offspring). The pending
//! mating lives in the optimizer's state and the random draws happen in the same order however
//! the units are grouped into steps, so slicing never changes the result. The evaluation cap
//! (`max_evaluations`) is checked before each initial individual and each new mating, never in
//! the middle of one.
//!
//! Greedy seeding ([`GaParams::greedy_seed_fraction`], off by default and for paper runs): with
//! k = ⌊fraction · μ⌋ > 0, the run first performs a greedy-insertion run
//! ([`GreedyInsertion`] with [`GreedyParams::default`]: the max-error rule, to every point, 64
//! recordings on a geometric sweep of T), one insertion per unit. Its non-dominated front
//! (n solutions, increasing T) then gives s = min(k, n) seeds at evenly spaced positions of
//! that list, index round(j·(n − 1)/(s − 1)) for j = 0..s (the middle one if s = 1); the
//! recordings are geometric in T, so this is an even spread in log T, like the random densities,
//! and it always includes the sparsest and the densest greedy mesh when s ≥ 2. The seeds are the
//! first s individuals, each scored by the GA like any individual (one evaluation, one unit);
//! the other μ − s are random with the log-spaced densities spread over μ − s slots. Only the
//! seeds reach the archive, not the rest of greedy's front, so the NSGA-II front does not
//! simply contain greedy's.
//!
//! Cost: every greedy insertion counts as an evaluation of this run ([`Progress::evaluations`]
//! includes them, and [`Nsga2::greedy_evaluations`] reports them alone), so a comparison at
//! equal evaluations charges the seeding; the evaluation cap applies to them too (checked before
//! each insertion). Greedy's own fresh scoring of its ≤ 64 recorded meshes is not counted, as
//! greedy insertion does not count it either. The unit that ends the greedy run (greedy's own
//! final unit, which records its last mesh) also picks the seeds.

use super::chromosome::Chromosome;
use super::mating::{MatingContext, PendingMating};
use super::oax::OaxRecord;
use super::operators;
use super::params::{GaParams, ParamsError};
use super::ranking::{crowding_distances, non_dominated_fronts, ranks_and_crowding, survivors};
use super::scorer::Scorer;
use super::trace::{GenerationTrace, MatingTrace, Member};
use crate::baselines::greedy_insertion::{GreedyInsertion, GreedyParams};
use crate::evaluator::Score;
use crate::front::Front;
use crate::heightfield::Heightfield;
use crate::optimizer::{Optimizer, Progress};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::Serialize;
use std::sync::Arc;

/// A member of the population.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Individual {
    /// Its kept set.
    pub genes: Chromosome,
    /// Its objectives.
    pub objectives: Score,
    /// Non-domination rank in the population (0 = non-dominated).
    pub rank: usize,
    /// Crowding distance within its rank (infinite at the ends of a front; JSON writes `null`).
    pub crowding: f64,
}

/// The NSGA-II optimizer; see the module doc.
pub struct Nsga2 {
    params: GaParams,
    seed: u64,
    mutation: f64,
    rng: Pcg64Mcg,
    scorer: Scorer,
    population: Vec<Individual>,
    offspring: Vec<Individual>,
    archive: Front,
    generation: u64,
    done: bool,
    /// The record of the last completed OAX crossover.
    last_crossover: Option<OaxRecord>,
    /// The mating in progress, if any.
    pending: Option<PendingMating>,
    /// True until greedy seeding has picked its seeds (false from the start when k = 0).
    seeding: bool,
    /// The greedy-insertion run of the seeding, while it runs.
    greedy: Option<Box<GreedyInsertion>>,
    /// Evaluations (insertions) the finished greedy run spent.
    greedy_evaluations: u64,
    /// The seeds' chromosomes, in the order they enter the population.
    seeds: Vec<Chromosome>,
    /// The generation being made, recorded for the teaching view.
    trace: GenerationTrace,
    /// The tournaments of the mating in progress.
    tournaments: [[usize; 2]; 2],
    /// The record of the last completed generation.
    last_trace: Option<GenerationTrace>,
}

impl Nsga2 {
    /// A run on `hf` with `params` and `seed`; nothing is evaluated until the first step.
    pub fn new(hf: Arc<Heightfield>, params: GaParams, seed: u64) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            mutation: params.mutation_on(&hf),
            rng: Pcg64Mcg::seed_from_u64(seed),
            scorer: Scorer::new(hf),
            population: Vec::with_capacity(params.population),
            offspring: Vec::with_capacity(params.population + 1),
            archive: Front::default(),
            generation: 0,
            done: false,
            last_crossover: None,
            pending: None,
            seeding: params.greedy_seeds() > 0,
            greedy: None,
            greedy_evaluations: 0,
            seeds: Vec::new(),
            trace: GenerationTrace::default(),
            tournaments: [[0; 2]; 2],
            last_trace: None,
            params,
            seed,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &GaParams {
        &self.params
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The current population with ranks and crowding distances (during initialisation, the
    /// individuals made so far, ranked among themselves once all μ exist; rank 0 and crowding 0
    /// before that).
    pub fn population(&self) -> &[Individual] {
        &self.population
    }

    /// The record of the last completed orthogonal-array crossover, if any happened (a
    /// crossover still making its children is not reported until it completes).
    pub fn last_crossover(&self) -> Option<&OaxRecord> {
        self.last_crossover.as_ref()
    }

    /// What the last completed generation did, phase by phase (see [`super::trace`]); `None`
    /// before the first generation completes.
    pub fn last_generation(&self) -> Option<&GenerationTrace> {
        self.last_trace.as_ref()
    }

    /// Evaluations spent by greedy seeding so far (0 when seeding is off); included in
    /// [`Progress::evaluations`].
    pub(crate) fn greedy_evaluations(&self) -> u64 {
        self.greedy_evaluations + self.greedy.as_ref().map_or(0, |g| g.progress().evaluations)
    }

    /// Every evaluation so far: the GA's and greedy seeding's.
    fn evaluations(&self) -> u64 {
        self.scorer.evaluations() + self.greedy_evaluations()
    }

    /// One unit of work (see the module doc).
    fn advance(&mut self) {
        if self.pending.is_none()
            && self
                .params
                .max_evaluations
                .is_some_and(|cap| self.evaluations() >= cap)
        {
            self.done = true;
            return;
        }
        if self.seeding {
            self.greedy_unit();
            return;
        }
        let mu = self.params.population;
        if self.population.len() < mu {
            self.initial_individual();
            if self.population.len() == mu {
                rank_and_crowd(&mut self.population);
                // The first crossovers' parents: kept pooled (and the pool sized for them).
                self.scorer
                    .keep_alive(self.population.iter().map(|i| &i.genes));
                self.done = self.params.generations == 0;
            }
            return;
        }
        self.mating();
        if self.pending.is_none() && self.offspring.len() >= mu {
            self.survival();
            self.generation += 1;
            self.done = self.generation >= self.params.generations as u64;
        }
    }

    /// One unit of the greedy seeding run (started at the first); picks the seeds when it ends.
    fn greedy_unit(&mut self) {
        let hf = self.scorer.heightfield().clone();
        let greedy = self.greedy.get_or_insert_with(|| {
            Box::new(
                GreedyInsertion::new(hf.clone(), GreedyParams::default())
                    .expect("the default greedy parameters are valid"),
            )
        });
        greedy.unit();
        if !greedy.progress().done {
            return;
        }
        let solutions = greedy.front().solutions();
        let n = solutions.len();
        let s = self.params.greedy_seeds().min(n);
        self.seeds = (0..s)
            .map(|j| {
                let index = if s == 1 {
                    (n - 1) / 2
                } else {
                    // round(j·(n − 1)/(s − 1)) in integers; distinct indices since s ≤ n.
                    (2 * j * (n - 1) + (s - 1)) / (2 * (s - 1))
                };
                Chromosome::from_indices(hf.len(), &solutions[index].kept)
            })
            .collect();
        self.greedy_evaluations = greedy.progress().evaluations;
        self.greedy = None;
        self.seeding = false;
    }

    fn initial_individual(&mut self) {
        let hf = self.scorer.heightfield().clone();
        let i = self.population.len();
        let seeded = self.seeds.len();
        let genes = if i < seeded {
            self.seeds[i].clone()
        } else {
            // The random individuals spread their densities over their own μ − s slots.
            let density = operators::initial_density(
                i - seeded,
                self.params.population - seeded,
                operators::free_genes(&hf),
                &mut self.rng,
            );
            operators::random_chromosome(&hf, density, &mut self.rng)
        };
        let objectives = self.scorer.score(&genes);
        self.archive.offer_score(objectives, || genes.indices());
        self.population.push(Individual {
            genes,
            objectives,
            rank: 0,
            crowding: 0.0,
        });
    }

    /// Binary tournament: the lower rank wins, then the larger crowding distance, then the
    /// first drawn. Returns the winner and the two drawn.
    fn tournament(&mut self) -> (usize, [usize; 2]) {
        let n = self.population.len();
        let (i, j) = (self.rng.random_range(0..n), self.rng.random_range(0..n));
        let (a, b) = (&self.population[i], &self.population[j]);
        let winner = if b.rank < a.rank || (b.rank == a.rank && b.crowding > a.crowding) {
            j
        } else {
            i
        };
        (winner, [i, j])
    }

    /// Makes the next child of the mating in progress, starting a new mating when none is;
    /// hands the two offspring over when the mating completes.
    fn mating(&mut self) {
        if self.pending.is_none() {
            if self.offspring.is_empty() {
                // The generation starts: record the population it starts from.
                self.trace = GenerationTrace {
                    generation: self.generation + 1,
                    parents: self.population.iter().map(member).collect(),
                    ..GenerationTrace::default()
                };
            }
            let ((i, drawn_i), (j, drawn_j)) = (self.tournament(), self.tournament());
            self.tournaments = [drawn_i, drawn_j];
            let w = self.rng.random::<f64>();
            let (a, b) = (&self.population[i], &self.population[j]);
            self.pending = Some(PendingMating::start(
                &self.params,
                self.scorer.scalarisation(w),
                (&a.genes, a.objectives),
                (&b.genes, b.objectives),
                &self.scorer,
                &mut self.rng,
            ));
            if let Some(p) = self.pending.as_mut() {
                p.parents = [i, j];
            }
        }
        let pending = self.pending.as_mut().expect("a mating is in progress");
        let archive = &mut self.archive;
        let Some(children) = pending.advance(
            MatingContext {
                mutation: self.mutation,
                rng: &mut self.rng,
                scorer: &mut self.scorer,
            },
            &mut |c, o| {
                archive.offer_score(*o, || c.indices());
            },
            &mut self.last_crossover,
        ) else {
            return;
        };
        let done = self.pending.take().expect("the mating just completed");
        self.trace.matings.push(MatingTrace {
            tournaments: self.tournaments,
            parents: done.parents,
            crossed: done.crossed,
            before_mutation: done.before_mutation,
            crossover_evaluations: done.crossover_evaluations,
            flipped: done.flipped,
            children: [children[0].1, children[1].1],
        });
        for (genes, objectives) in children {
            if self.offspring.len() < self.params.population {
                self.trace.offspring.push(objectives);
                self.offspring.push(Individual {
                    genes,
                    objectives,
                    rank: 0,
                    crowding: 0.0,
                });
            }
        }
    }

    /// (μ + λ) survival by rank, then crowding distance.
    fn survival(&mut self) {
        let mu = self.params.population;
        let mut union: Vec<Option<Individual>> = self
            .population
            .drain(..)
            .chain(self.offspring.drain(..))
            .map(Some)
            .collect();
        let points: Vec<[f64; 2]> = union
            .iter()
            .map(|s| s.as_ref().expect("all present").objectives.objectives())
            .collect();
        let fronts = non_dominated_fronts(&points);
        self.trace.union = union
            .iter()
            .map(|s| member(s.as_ref().expect("all present")))
            .collect();
        for (rank, front) in fronts.iter().enumerate() {
            for (&i, d) in front.iter().zip(crowding_distances(&points, front)) {
                self.trace.union[i].rank = rank;
                self.trace.union[i].crowding = d;
            }
        }
        for k in survivors(&points, &fronts, mu) {
            self.trace.survivors.push(k);
            self.population
                .push(union[k].take().expect("each index is in one front"));
        }
        rank_and_crowd(&mut self.population);
        self.scorer
            .keep_alive(self.population.iter().map(|i| &i.genes));
        self.last_trace = Some(std::mem::take(&mut self.trace));
    }
}

fn member(i: &Individual) -> Member {
    Member {
        objectives: i.objectives,
        rank: i.rank,
        crowding: i.crowding,
    }
}

/// Sets every individual's rank and crowding distance within `population`.
fn rank_and_crowd(population: &mut [Individual]) {
    let points: Vec<[f64; 2]> = population
        .iter()
        .map(|s| s.objectives.objectives())
        .collect();
    for (i, (rank, crowding)) in population.iter_mut().zip(ranks_and_crowding(&points)) {
        (i.rank, i.crowding) = (rank, crowding);
    }
}

impl Optimizer for Nsga2 {
    /// Unit: one evaluation (see the module doc), so `step(1)` spends at most one.
    fn unit(&mut self) {
        self.advance();
    }

    fn front(&self) -> &Front {
        &self.archive
    }

    fn progress(&self) -> Progress {
        Progress {
            evaluations: self.evaluations(),
            generation: self.generation,
            done: self.done,
        }
    }
}
