//! The weighted-sum single-objective GA (the paper's extension of Huang & Ho's IGA): one GA run
//! per weight w ∈ {0, 0.1, …, 1} minimising F = w·E/E₀ + (1 − w)·T/T₀ ([`Scalarisation`]:
//! E₀ = E of the corner-only mesh, T₀ = 2(W − 1)(H − 1)). The best solution of each run enters
//! the front, which therefore holds at most one solution per weight.
//!
//! Each run: μ random individuals (the same log-spaced densities as NSGA-II), then per
//! generation λ = μ offspring from binary tournaments on F, crossover with probability p_c (OAX
//! with this F directly in its factor analysis), bit-flip mutation; elitist (μ + λ) truncation
//! to the μ best F. Each run gets the same population and generations as one NSGA-II run, so the
//! whole optimizer spends about 11 times NSGA-II's evaluations. A cap on evaluations
//! (`max_evaluations`) is shared equally between the runs, so every weight still runs.
//!
//! Unit of work ([`crate::optimizer`]): one evaluation, as in NSGA-II. A unit creates one
//! initial individual of the current run, or makes the next child of the mating in progress
//! (one OAX row, the best-levels child, or one mutated offspring; see `evolution::mating`). The
//! survival step and the end of a run happen in the unit that completes them; a run's end (its
//! generations or its share of the evaluation cap) is only checked between matings, never in
//! the middle of one. The pending mating lives in the optimizer's state and the random draws
//! happen in the same order however the units are grouped, so slicing never changes the
//! result.

use super::chromosome::Chromosome;
use super::mating::{MatingContext, PendingMating};
use super::oax::OaxRecord;
use super::operators;
use super::params::{GaParams, ParamsError};
use super::scalarisation::Scalarisation;
use super::scorer::Scorer;
use crate::evaluator::Score;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use crate::optimizer::{Optimizer, Progress};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Parameters: those of each run, and the weights (one run each, in this order).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct WeightedSumParams {
    /// The GA parameters of every run.
    #[serde(flatten)]
    pub ga: GaParams,
    /// The weights w of E; paper: 0, 0.1, …, 1.
    pub weights: Vec<f64>,
}

impl Default for WeightedSumParams {
    fn default() -> Self {
        Self {
            ga: GaParams::default(),
            weights: (0..=10).map(|k| k as f64 / 10.0).collect(),
        }
    }
}

#[derive(Clone, Debug)]
struct Member {
    genes: Chromosome,
    objectives: Score,
    fitness: f64,
}

/// The weighted-sum GA; see the module doc.
pub struct WeightedSum {
    params: WeightedSumParams,
    mutation: f64,
    rng: Pcg64Mcg,
    scorer: Scorer,
    front: Front,
    run_bests: Vec<(f64, Solution)>,
    /// Index of the current weight.
    run: usize,
    run_start: u64,
    run_generation: u64,
    generations_done: u64,
    population: Vec<Member>,
    offspring: Vec<Member>,
    best: Option<Member>,
    done: bool,
    /// The record of the last completed OAX crossover.
    last_crossover: Option<OaxRecord>,
    /// The mating in progress, if any.
    pending: Option<PendingMating>,
}

impl WeightedSum {
    /// A run on `hf` with `params` and `seed`; nothing is evaluated until the first step.
    pub(crate) fn new(
        hf: Arc<Heightfield>,
        params: WeightedSumParams,
        seed: u64,
    ) -> Result<Self, ParamsError> {
        params.ga.validate()?;
        if params.weights.is_empty() || params.weights.iter().any(|w| !(0.0..=1.0).contains(w)) {
            return Err(ParamsError::BadWeights);
        }
        // Seeding is NSGA-II's option: 11 single-objective runs would each need their own
        // choice of which greedy solutions suit their weight, which the method does not define.
        if params.ga.greedy_seed_fraction > 0.0 {
            return Err(ParamsError::SeedingUnsupported);
        }
        Ok(Self {
            mutation: params.ga.mutation_on(&hf),
            rng: Pcg64Mcg::seed_from_u64(seed),
            scorer: Scorer::new(hf),
            front: Front::default(),
            run_bests: Vec::new(),
            run: 0,
            run_start: 0,
            run_generation: 0,
            generations_done: 0,
            population: Vec::new(),
            offspring: Vec::new(),
            best: None,
            done: false,
            last_crossover: None,
            pending: None,
            params,
        })
    }

    /// The best solution of each finished run, with its weight, in run order.
    #[cfg(test)]
    pub(crate) fn run_bests(&self) -> &[(f64, Solution)] {
        &self.run_bests
    }

    /// The record of the last completed orthogonal-array crossover, if any happened (a
    /// crossover still making its children is not reported until it completes).
    #[cfg(test)]
    pub(crate) fn last_crossover(&self) -> Option<&OaxRecord> {
        self.last_crossover.as_ref()
    }

    fn scalar(&self) -> Scalarisation {
        self.scorer.scalarisation(self.params.weights[self.run])
    }

    /// Scores `genes` and remembers it when it is the run's best so far.
    fn note(best: &mut Option<Member>, genes: &Chromosome, objectives: Score, fitness: f64) {
        if best.as_ref().is_none_or(|b| fitness < b.fitness) {
            *best = Some(Member {
                genes: genes.clone(),
                objectives,
                fitness,
            });
        }
    }

    fn advance(&mut self) {
        let mu = self.params.ga.population;
        if self.population.len() < mu {
            let hf = self.scorer.heightfield().clone();
            let i = self.population.len();
            let density =
                operators::initial_density(i, mu, operators::free_genes(&hf), &mut self.rng);
            let genes = operators::random_chromosome(&hf, density, &mut self.rng);
            let objectives = self.scorer.score(&genes);
            let fitness = self.scalar().value(&objectives);
            Self::note(&mut self.best, &genes, objectives, fitness);
            self.population.push(Member {
                genes,
                objectives,
                fitness,
            });
            if self.population.len() == mu {
                // The first crossovers' parents: kept pooled (and the pool sized for them).
                self.scorer
                    .keep_alive(self.population.iter().map(|m| &m.genes));
            }
        } else {
            self.mating();
            if self.pending.is_some() {
                // Mid-mating: neither survival nor the end of the run can come yet.
                return;
            }
            if self.offspring.len() >= mu {
                self.survival();
                self.run_generation += 1;
                self.generations_done += 1;
            }
        }
        let share = self
            .params
            .ga
            .max_evaluations
            .map(|cap| (cap / self.params.weights.len() as u64).max(1));
        let run_done = (self.population.len() >= mu
            && self.run_generation >= self.params.ga.generations as u64)
            || share.is_some_and(|s| self.scorer.evaluations() - self.run_start >= s);
        if run_done {
            self.finish_run();
        }
    }

    /// Makes the next child of the mating in progress, starting a new mating when none is;
    /// hands the two offspring over when the mating completes.
    fn mating(&mut self) {
        let scalar = self.scalar();
        if self.pending.is_none() {
            let (i, j) = (self.tournament(), self.tournament());
            let (a, b) = (&self.population[i], &self.population[j]);
            self.pending = Some(PendingMating::start(
                &self.params.ga,
                scalar,
                (&a.genes, a.objectives),
                (&b.genes, b.objectives),
                &self.scorer,
                &mut self.rng,
            ));
        }
        let pending = self.pending.as_mut().expect("a mating is in progress");
        let best = &mut self.best;
        let Some(children) = pending.advance(
            MatingContext {
                mutation: self.mutation,
                rng: &mut self.rng,
                scorer: &mut self.scorer,
            },
            &mut |c, o| Self::note(best, c, *o, scalar.value(o)),
            &mut self.last_crossover,
        ) else {
            return;
        };
        self.pending = None;
        for (genes, objectives) in children {
            if self.offspring.len() < self.params.ga.population {
                self.offspring.push(Member {
                    fitness: scalar.value(&objectives),
                    genes,
                    objectives,
                });
            }
        }
    }

    /// Binary tournament on F; ties go to the first drawn.
    fn tournament(&mut self) -> usize {
        let n = self.population.len();
        let (i, j) = (self.rng.random_range(0..n), self.rng.random_range(0..n));
        if self.population[j].fitness < self.population[i].fitness {
            j
        } else {
            i
        }
    }

    /// Elitist (μ + λ): the μ best F of parents and offspring (ties by position).
    fn survival(&mut self) {
        let mut union: Vec<Member> = self.population.drain(..).collect();
        union.append(&mut self.offspring);
        let mut order: Vec<usize> = (0..union.len()).collect();
        order.sort_by(|&a, &b| {
            union[a]
                .fitness
                .total_cmp(&union[b].fitness)
                .then(a.cmp(&b))
        });
        let mut slots: Vec<Option<Member>> = union.into_iter().map(Some).collect();
        self.population = order[..self.params.ga.population]
            .iter()
            .map(|&k| slots[k].take().expect("each index once"))
            .collect();
        self.scorer
            .keep_alive(self.population.iter().map(|m| &m.genes));
    }

    fn finish_run(&mut self) {
        if let Some(best) = self.best.take() {
            let solution = Solution {
                score: best.objectives,
                kept: best.genes.indices(),
            };
            self.front.offer(solution.clone());
            self.run_bests
                .push((self.params.weights[self.run], solution));
        }
        self.population.clear();
        self.offspring.clear();
        // The next run starts from a new population: nothing of this one needs keeping.
        self.scorer.keep_alive([]);
        self.run_generation = 0;
        self.run_start = self.scorer.evaluations();
        self.run += 1;
        self.done = self.run >= self.params.weights.len();
    }
}

impl Optimizer for WeightedSum {
    /// Unit: one evaluation (see the module doc), so `step(1)` spends at most one.
    fn unit(&mut self) {
        self.advance();
    }

    fn front(&self) -> &Front {
        &self.front
    }

    /// `generation` counts the generations completed over all runs so far.
    fn progress(&self) -> Progress {
        Progress {
            evaluations: self.scorer.evaluations(),
            generation: self.generations_done,
            done: self.done,
        }
    }
}
