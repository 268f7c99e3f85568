//! NSGA-II (Deb et al. 2002) on (E_sum, T) with orthogonal-array crossover.
//!
//! - Initial population: μ random individuals with log-spaced densities
//!   ([`operators::initial_density`]).
//! - Each generation makes λ = μ offspring: two parents by binary tournament on (rank, then
//!   larger crowding distance), crossover with probability p_c, bit-flip mutation, evaluation.
//! - Elitist (μ + λ) survival: the union is sorted into non-dominated fronts, whole fronts are
//!   kept while they fit, and the last one is cut by decreasing crowding distance. Rank and
//!   crowding are then recomputed on the survivors for the next tournaments.
//! - The archive ([`Optimizer::front`]) receives *every* evaluated chromosome, OAX rows
//!   included, so it is the front of everything seen.
//!
//! OAX's factor analysis needs a scalar fitness. Here it is the normalised weighted sum
//! F = w·E/E₀ + (1 − w)·T/T₀ ([`Scalarisation`](super::objectives::Scalarisation)) with a fresh random w ~ U(0, 1) per crossover.
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
//! one mutated offspring (see [`super::mating`]). A child whose objectives are already known
//! costs no evaluation and its unit does no work beyond bookkeeping; the same holds for starting
//! a mating (two tournaments, the weight and the crossover's random choices, drawn at its first
//! unit) and for the survival step (run by the unit that completes the offspring). The pending
//! mating lives in the optimizer's state and the random draws happen in the same order however
//! the units are grouped into steps, so slicing never changes the result. The evaluation cap
//! (`max_evaluations`) is checked before each initial individual and each new mating, never in
//! the middle of one.

use super::chromosome::Chromosome;
use super::mating::{MatingContext, PendingMating};
use super::oax::OaxRecord;
use super::objectives::{Objectives, Scorer, offer};
use super::operators;
use super::params::{GaParams, ParamsError};
use super::ranking::{crowding_distances, non_dominated_fronts};
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
    pub objectives: Objectives,
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

    /// One unit of work (see the module doc).
    fn advance(&mut self) {
        if self.pending.is_none()
            && self
                .params
                .max_evaluations
                .is_some_and(|cap| self.scorer.evaluations() >= cap)
        {
            self.done = true;
            return;
        }
        let mu = self.params.population;
        if self.population.len() < mu {
            self.initial_individual();
            if self.population.len() == mu {
                rank_and_crowd(&mut self.population);
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

    fn initial_individual(&mut self) {
        let hf = self.scorer.heightfield().clone();
        let i = self.population.len();
        let density = operators::initial_density(
            i,
            self.params.population,
            operators::free_genes(&hf),
            &mut self.rng,
        );
        let genes = operators::random_chromosome(&hf, density, &mut self.rng);
        let objectives = self.scorer.score(&genes);
        offer(&mut self.archive, &genes, &objectives);
        self.population.push(Individual {
            genes,
            objectives,
            rank: 0,
            crowding: 0.0,
        });
    }

    /// Binary tournament: the lower rank wins, then the larger crowding distance, then the
    /// first drawn.
    fn tournament(&mut self) -> usize {
        let n = self.population.len();
        let (i, j) = (self.rng.random_range(0..n), self.rng.random_range(0..n));
        let (a, b) = (&self.population[i], &self.population[j]);
        if b.rank < a.rank || (b.rank == a.rank && b.crowding > a.crowding) {
            j
        } else {
            i
        }
    }

    /// Makes the next child of the mating in progress, starting a new mating when none is;
    /// hands the two offspring over when the mating completes.
    fn mating(&mut self) {
        if self.pending.is_none() {
            let (i, j) = (self.tournament(), self.tournament());
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
                offer(archive, c, o);
            },
            &mut self.last_crossover,
        ) else {
            return;
        };
        self.pending = None;
        for (genes, objectives) in children {
            if self.offspring.len() < self.params.population {
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
            .map(|s| s.as_ref().expect("all present").objectives.pair())
            .collect();
        for front in non_dominated_fronts(&points) {
            let room = mu - self.population.len();
            if room == 0 {
                break;
            }
            let chosen: Vec<usize> = if front.len() <= room {
                front
            } else {
                let d = crowding_distances(&points, &front);
                let mut order: Vec<usize> = (0..front.len()).collect();
                order.sort_by(|&a, &b| d[b].total_cmp(&d[a]).then(a.cmp(&b)));
                order[..room].iter().map(|&k| front[k]).collect()
            };
            for k in chosen {
                self.population
                    .push(union[k].take().expect("each index is in one front"));
            }
        }
        rank_and_crowd(&mut self.population);
    }
}

/// Sets every individual's rank and crowding distance within `population`.
fn rank_and_crowd(population: &mut [Individual]) {
    let points: Vec<[f64; 2]> = population.iter().map(|s| s.objectives.pair()).collect();
    for (rank, front) in non_dominated_fronts(&points).iter().enumerate() {
        for (&i, d) in front.iter().zip(crowding_distances(&points, front)) {
            population[i].rank = rank;
            population[i].crowding = d;
        }
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
            evaluations: self.scorer.evaluations(),
            generation: self.generation,
            done: self.done,
        }
    }
}
