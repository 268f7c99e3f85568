//! The memetic optimizer: NSGA-II's loop with guided operators and local search.

use super::decimation::{self, Decimation};
use super::local_search::LocalSearch;
use super::member::{LookupPool, Member, offer};
use super::mutation::{self, Operator};
use super::neighbour_mating::{self, Cut};
use super::params::{MemeticParams, MemeticParamsError};
use super::seeding::{self, Seeding};
use crate::evaluator::Evaluator;
use crate::evolution::ranking::{non_dominated_fronts, ranks_and_crowding, survivors};
use crate::front::Front;
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use crate::optimizer::{Optimizer, Progress};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;

/// The share of the evaluations after seeding that goes to the local search: a generation's
/// local-search phase runs its [`MemeticParams::local_search_rounds`] units and then goes on
/// until the local search holds this share, so that the split between offspring and local
/// search does not drift with how many evaluations a round happens to cost.
pub const LOCAL_SEARCH_SHARE: f64 = 0.98;

/// Where a generation stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    /// Making offspring (survival runs in the unit that completes them).
    Offspring,
    /// Local-search rounds, this many left.
    LocalSearch(usize),
}

/// The memetic NSGA-II; see the module doc of [`super`].
pub struct Memetic {
    params: MemeticParams,
    seed: u64,
    budget: u64,
    rng: Pcg64Mcg,
    evaluator: Evaluator,
    seeding: Seeding,
    /// The decimation of the first greedy run's dense mesh, once seeding is done.
    decimation: Option<Decimation>,
    /// Both greedy runs' fronts merged: what the memetic front must weakly dominate.
    seed_front: Front,
    /// The seeds' kept sets, once seeding is done, in the order they join.
    seeds: Vec<Vec<u32>>,
    /// The random initial kept sets were drawn (when greedy seeding is off).
    randomly_seeded: bool,
    /// Stowed between uses ([`Member::stow`]), as are the offspring.
    population: Vec<Member>,
    offspring: Vec<Member>,
    lookups: LookupPool,
    archive: Front,
    local: LocalSearch,
    stage: Stage,
    generation: u64,
    /// Evaluations after seeding.
    evaluations: u64,
    /// Of those, the local search's.
    local_evaluations: u64,
    done: bool,
}

impl Memetic {
    /// A run on `hf` with `params` and `seed`; nothing is evaluated until the first unit.
    pub fn new(
        hf: Arc<Heightfield>,
        params: MemeticParams,
        seed: u64,
    ) -> Result<Self, MemeticParamsError> {
        params.validate()?;
        Ok(Self {
            budget: params.budget(&hf),
            rng: Pcg64Mcg::seed_from_u64(seed),
            evaluator: Evaluator::new(hf.clone()),
            seeding: Seeding::new(hf.clone()),
            decimation: None,
            seed_front: Front::new(params.error),
            seeds: Vec::new(),
            randomly_seeded: false,
            population: Vec::with_capacity(params.population),
            offspring: Vec::with_capacity(params.population),
            lookups: LookupPool::default(),
            archive: Front::new(params.error),
            local: LocalSearch::new(&hf),
            stage: Stage::Offspring,
            generation: 0,
            evaluations: 0,
            local_evaluations: 0,
            done: false,
            params,
            seed,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &MemeticParams {
        &self.params
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The evaluation budget the run stops at.
    pub fn budget(&self) -> u64 {
        self.budget
    }

    /// The greedy seeding runs' fronts merged (empty until seeding is done).
    pub fn seed_front(&self) -> &Front {
        &self.seed_front
    }

    /// The current population.
    pub fn population(&self) -> &[Member] {
        &self.population
    }

    /// The local search's evaluations due by now: its [`LOCAL_SEARCH_SHARE`] of those after
    /// seeding.
    fn local_search_due(&self) -> u64 {
        (self.evaluations as f64 * LOCAL_SEARCH_SHARE) as u64
    }

    fn total_evaluations(&self) -> u64 {
        self.seeding.evaluations()
            + self.decimation.as_ref().map_or(0, Decimation::evaluations)
            + self.evaluations
    }

    fn advance(&mut self) {
        if self.total_evaluations() >= self.budget {
            // A budget smaller than the seeding still ends with a front: the sweeps'
            // recordings so far, already offered.
            self.done = true;
            return;
        }
        if !self.params.greedy_seeding {
            if !self.randomly_seeded {
                let hf = self.evaluator.heightfield().clone();
                self.seeds = seeding::random_seeds(&hf, self.params.population, &mut self.rng);
                self.seeds.reverse();
                self.randomly_seeded = true;
                return;
            }
        } else if !self.seeding.is_done() {
            let (archive, seed_front) = (&mut self.archive, &mut self.seed_front);
            self.seeding.unit(|s| {
                archive.offer(s.clone());
                seed_front.offer(s.clone());
            });
            return;
        } else if !self.decimation.as_ref().is_some_and(Decimation::is_done) {
            let (seeding, evaluator) = (&self.seeding, &mut self.evaluator);
            let archive_measure = self.params.error;
            let run = self.decimation.get_or_insert_with(|| {
                let hf = evaluator.heightfield().clone();
                let start = seeding.decimation_start(decimation::start_triangles(&hf));
                Decimation::new(evaluator, start, archive_measure)
            });
            let archive = &mut self.archive;
            run.unit(evaluator, |kept, score| {
                offer(archive, kept, score);
            });
            if run.is_done() {
                let hf = self.evaluator.heightfield().clone();
                self.seeds = seeding::seeds(&hf, &self.archive, self.params.population);
                self.seeds.reverse();
            }
            return;
        }
        if let Some(kept) = self.seeds.pop() {
            let mut member = Member::fresh(&mut self.evaluator, kept);
            member.stow(&mut self.lookups);
            self.evaluations += 1;
            offer(&mut self.archive, &member.kept, &member.score);
            self.population.push(member);
            if self.seeds.is_empty() {
                rank_and_crowd(&mut self.population, self.params.error);
            }
            return;
        }
        match self.stage {
            Stage::Offspring if self.population.len() >= 2 => {
                self.child();
                if self.offspring.len() >= self.params.population {
                    self.survival();
                    if self.params.local_search {
                        self.stage = Stage::LocalSearch(self.params.local_search_rounds);
                    } else {
                        self.generation += 1;
                    }
                }
            }
            Stage::Offspring if self.params.local_search => {
                // Too few seeds to mate (a tiny grid): local search only.
                self.stage = Stage::LocalSearch(self.params.local_search_rounds.max(1));
            }
            Stage::Offspring => {
                // Too few seeds to mate and no local search: nothing can improve the front.
                self.done = true;
            }
            Stage::LocalSearch(left) => {
                if left > 0 || self.local_evaluations < self.local_search_due() {
                    let before = self.evaluations;
                    self.local.unit(
                        &mut self.evaluator,
                        &mut self.archive,
                        &mut self.rng,
                        &mut self.evaluations,
                    );
                    self.local_evaluations += self.evaluations - before;
                }
                if left <= 1 && self.local_evaluations >= self.local_search_due() {
                    self.generation += 1;
                    self.stage = Stage::Offspring;
                } else {
                    self.stage = Stage::LocalSearch(left.saturating_sub(1));
                }
            }
        }
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

    /// Makes one child: a crossover of a parent with a neighbour in T (with the crossover
    /// probability) or a copy of the parent, then one guided mutation.
    fn child(&mut self) {
        let hf = self.evaluator.heightfield().clone();
        let a = self.tournament();
        let crossed = self.rng.random::<f64>() < self.params.crossover_probability;
        let mate = if !crossed {
            None
        } else if self.params.neighbour_mating {
            neighbour_mating::pick_mate(&self.population, a, &mut self.rng)
        } else {
            neighbour_mating::pick_any_mate(&self.population, a, &mut self.rng)
        };
        let mut child = match mate {
            Some(b) => {
                let cut = Cut::draw(&hf, &mut self.rng);
                let (pa, pb) = two_mut(&mut self.population, a, b);
                pa.unstow(&mut self.lookups);
                pb.unstow(&mut self.lookups);
                let c = neighbour_mating::cross(&mut self.evaluator, pa, pb, cut);
                pa.stow(&mut self.lookups);
                pb.stow(&mut self.lookups);
                self.evaluations += 1;
                offer(&mut self.archive, &c.kept, &c.score);
                c
            }
            None => {
                // The parent keeps the guide its copy needs, for its next copies.
                let parent = &mut self.population[a];
                parent.guide(&hf);
                let mut copy = parent.clone();
                copy.unstow(&mut self.lookups);
                copy
            }
        };
        if !self.params.guided_mutation {
            if let Some(edit) = mutation::random_flip(&hf, &child, &mut self.rng) {
                child.apply(&mut self.evaluator, &edit);
                self.evaluations += 1;
                offer(&mut self.archive, &child.kept, &child.score);
            }
            child.stow(&mut self.lookups);
            self.offspring.push(child);
            return;
        }
        child.guide(&hf);
        let edit = match Operator::draw(&mut self.rng) {
            Operator::Insert => mutation::insert(&hf, child.guide(&hf), &mut self.rng),
            Operator::Remove => mutation::remove(child.guide(&hf), &mut self.rng),
            Operator::Move => {
                child.ready_for_trials();
                mutation::best_move(
                    &mut self.evaluator,
                    &child,
                    self.params.error,
                    &mut self.rng,
                    &mut self.evaluations,
                )
                .map(|(edit, _)| edit)
            }
        };
        if let Some(edit) = edit {
            child.apply(&mut self.evaluator, &edit);
            self.evaluations += 1;
            offer(&mut self.archive, &child.kept, &child.score);
        }
        child.stow(&mut self.lookups);
        self.offspring.push(child);
    }

    /// (μ + λ) survival by rank, then crowding distance, as NSGA-II.
    fn survival(&mut self) {
        let mu = self.params.population;
        let mut union: Vec<Option<Member>> = self
            .population
            .drain(..)
            .chain(self.offspring.drain(..))
            .map(Some)
            .collect();
        let points: Vec<[f64; 2]> = union
            .iter()
            .map(|m| m.as_ref().expect("all present").pair(self.params.error))
            .collect();
        for k in survivors(&points, &non_dominated_fronts(&points), mu) {
            self.population
                .push(union[k].take().expect("each index is in one front"));
        }
        rank_and_crowd(&mut self.population, self.params.error);
    }
}

/// Mutable references to two different members.
fn two_mut(v: &mut [Member], a: usize, b: usize) -> (&mut Member, &mut Member) {
    assert_ne!(a, b, "a mate is another member");
    if a < b {
        let (lo, hi) = v.split_at_mut(b);
        (&mut lo[a], &mut hi[0])
    } else {
        let (lo, hi) = v.split_at_mut(a);
        (&mut hi[0], &mut lo[b])
    }
}

/// Sets every member's rank and crowding distance within `population`.
fn rank_and_crowd(population: &mut [Member], measure: ErrorMeasure) {
    let points: Vec<[f64; 2]> = population.iter().map(|m| m.pair(measure)).collect();
    for (m, (rank, crowding)) in population.iter_mut().zip(ranks_and_crowding(&points)) {
        (m.rank, m.crowding) = (rank, crowding);
    }
}

impl Optimizer for Memetic {
    /// Unit: one greedy insertion while seeding, then one decimation unit (a batch of first
    /// costs, or one removal with its neighbours' new costs); then one seed's scoring, one
    /// child (a crossover and a mutation, up to 10 evaluations with a move's trials), or one
    /// local-search step (a visit's start, one padding step, or a round or the part of it that
    /// its [`TRIALS_PER_UNIT`](super::local_search::TRIALS_PER_UNIT) new trials allow).
    fn unit(&mut self) {
        self.advance();
    }

    fn front(&self) -> &Front {
        &self.archive
    }

    fn progress(&self) -> Progress {
        Progress {
            evaluations: self.total_evaluations(),
            generation: self.generation,
            done: self.done,
        }
    }
}
