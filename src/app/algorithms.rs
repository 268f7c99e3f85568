//! The algorithms the app offers, their parameters (the source paper's defaults), and the one
//! place that builds a running algorithm from them.

use crate::baselines::{DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams};
use crate::evolution::oax::OaxRecord;
use crate::evolution::trace::GenerationTrace;
use crate::evolution::{
    CrossoverKind, GaParams, Memetic, MemeticParams, Nsga2, WeightedSum, WeightedSumParams,
};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// An algorithm the app can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Algorithm {
    /// The memetic NSGA-II, the project's own method and the app's default: greedy seeds,
    /// error-guided operators and local search (its own parameters; only the seed is the form's).
    Memetic,
    /// NSGA-II with the chosen crossover (the paper's method with orthogonal-array crossover).
    Nsga2,
    /// A GA on weighted sums of E and T, one run per weight (0, 0.1, …, 1).
    WeightedSum,
    /// Greedy insertion (Garland & Heckbert 1995).
    GreedyInsertion,
    /// Edge decimation.
    Decimation,
}

impl Algorithm {
    /// Every algorithm, in the order of the menu.
    pub const ALL: [Algorithm; 5] = [
        Algorithm::Memetic,
        Algorithm::Nsga2,
        Algorithm::WeightedSum,
        Algorithm::GreedyInsertion,
        Algorithm::Decimation,
    ];

    /// The algorithm a new app runs: the project's best method.
    pub const DEFAULT: Algorithm = Algorithm::Memetic;

    /// The menu's value for this algorithm, also its name in front.json (as the CLI spells it).
    pub fn key(self) -> &'static str {
        match self {
            Algorithm::Memetic => "memetic",
            Algorithm::Nsga2 => "nsga2",
            Algorithm::WeightedSum => "weighted",
            Algorithm::GreedyInsertion => "greedy",
            Algorithm::Decimation => "decimation",
        }
    }

    /// The algorithm with menu value `key`.
    pub fn from_key(key: &str) -> Option<Algorithm> {
        Self::ALL.into_iter().find(|a| a.key() == key)
    }

    /// Name for people.
    pub fn label(self) -> &'static str {
        match self {
            Algorithm::Memetic => "memetic NSGA-II",
            Algorithm::Nsga2 => "NSGA-II",
            Algorithm::WeightedSum => "weighted-sum GA",
            Algorithm::GreedyInsertion => "greedy insertion",
            Algorithm::Decimation => "edge decimation",
        }
    }

    /// True when [`build`] reads `field` of the form for this algorithm: every field for the two
    /// GAs, only the seed for the memetic method (it runs with its own parameters), none for the
    /// deterministic classical methods.
    pub fn uses(self, field: Field) -> bool {
        match self {
            Algorithm::Nsga2 | Algorithm::WeightedSum => true,
            Algorithm::Memetic => field == Field::Seed,
            Algorithm::GreedyInsertion | Algorithm::Decimation => false,
        }
    }
}

/// A field of the parameter form (a member of [`Params`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// [`Params::population`].
    Population,
    /// [`Params::generations`].
    Generations,
    /// [`Params::crossover`].
    Crossover,
    /// [`Params::crossover_probability`].
    CrossoverProbability,
    /// [`Params::mutation_probability`].
    MutationProbability,
    /// [`Params::seed`].
    Seed,
}

impl Field {
    /// Every field, in the form's order.
    pub const ALL: [Field; 6] = [
        Field::Population,
        Field::Generations,
        Field::Crossover,
        Field::CrossoverProbability,
        Field::MutationProbability,
        Field::Seed,
    ];

    /// The id of the field's input in the page.
    pub fn id(self) -> &'static str {
        match self {
            Field::Population => "population",
            Field::Generations => "generations",
            Field::Crossover => "crossover",
            Field::CrossoverProbability => "crossover-probability",
            Field::MutationProbability => "mutation-probability",
            Field::Seed => "seed",
        }
    }
}

/// The menu value of a crossover kind (its serde name).
pub fn crossover_key(kind: CrossoverKind) -> &'static str {
    match kind {
        CrossoverKind::Oax => "oax",
        CrossoverKind::Uniform => "uniform",
        CrossoverKind::TwoPoint => "two-point",
    }
}

/// The crossover kind with menu value `key`.
pub fn crossover_from_key(key: &str) -> Option<CrossoverKind> {
    [
        CrossoverKind::Oax,
        CrossoverKind::Uniform,
        CrossoverKind::TwoPoint,
    ]
    .into_iter()
    .find(|k| crossover_key(*k) == key)
}

/// Parameters of a run, with the source paper's defaults.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// Population size (paper: 100).
    pub population: usize,
    /// Generations (paper: 50).
    pub generations: usize,
    /// Crossover operator (paper: orthogonal-array crossover).
    pub crossover: CrossoverKind,
    /// Crossover probability (paper: 0.8).
    pub crossover_probability: f64,
    /// Per-gene mutation probability; `None` means 1/L with L the chromosome length.
    pub mutation_probability: Option<f64>,
    /// Seed of the run's single random generator.
    pub seed: u64,
}

impl Default for Params {
    fn default() -> Self {
        let ga = GaParams::default();
        Self {
            population: ga.population,
            generations: ga.generations,
            crossover: ga.crossover,
            crossover_probability: ga.crossover_probability,
            mutation_probability: ga.mutation_probability,
            seed: 1,
        }
    }
}

impl Params {
    /// The GA parameters these stand for (the other fields at their defaults).
    pub fn ga(&self) -> GaParams {
        GaParams {
            population: self.population,
            generations: self.generations,
            crossover: self.crossover,
            crossover_probability: self.crossover_probability,
            mutation_probability: self.mutation_probability,
            ..GaParams::default()
        }
    }

    /// Checks the ranges; the message says which field is wrong and what is allowed. Upper
    /// bounds keep a browser tab's run finite.
    pub fn validate(&self) -> Result<(), String> {
        if self.population > 10_000 {
            return Err(format!(
                "population must be at most 10000, got {}",
                self.population
            ));
        }
        if !(1..=100_000).contains(&self.generations) {
            return Err(format!(
                "generations must be between 1 and 100000, got {}",
                self.generations
            ));
        }
        self.ga().validate().map_err(|e| e.to_string())
    }
}

/// A running algorithm: an [`Optimizer`] plus what the views show beyond its front.
pub trait Running: Optimizer {
    /// The current population as (T, E, non-domination rank); empty for methods without one.
    fn population_points(&self) -> Vec<(f64, f64, usize)> {
        Vec::new()
    }
    /// What the last completed generation did, phase by phase (NSGA-II only).
    fn generation_trace(&self) -> Option<&GenerationTrace> {
        None
    }
    /// The last completed orthogonal-array crossover (NSGA-II only).
    fn last_crossover(&self) -> Option<&OaxRecord> {
        None
    }
    /// The run as a pool run, when its work happens in Web Workers (see [`super::pool`]).
    fn as_pool(&mut self) -> Option<&mut super::pool::PoolRun> {
        None
    }
    /// [`Running::as_pool`], to read.
    fn as_pool_ref(&self) -> Option<&super::pool::PoolRun> {
        None
    }
}

impl Running for Nsga2 {
    fn population_points(&self) -> Vec<(f64, f64, usize)> {
        self.population()
            .iter()
            .map(|i| (i.objectives.t as f64, i.objectives.e_sum, i.rank))
            .collect()
    }
    fn generation_trace(&self) -> Option<&GenerationTrace> {
        self.last_generation()
    }
    fn last_crossover(&self) -> Option<&OaxRecord> {
        Nsga2::last_crossover(self)
    }
}
impl Running for Memetic {
    fn population_points(&self) -> Vec<(f64, f64, usize)> {
        self.population()
            .iter()
            .map(|m| (m.score.t as f64, m.score.e_sum, m.rank))
            .collect()
    }
}
impl Running for WeightedSum {}
impl Running for GreedyInsertion {}
impl Running for EdgeDecimation {}

/// The parameters as front.json records them (the same JSON as `paretomesh run --out`).
pub fn params_json(algorithm: Algorithm, params: &Params) -> serde_json::Value {
    let value = match algorithm {
        Algorithm::Memetic => serde_json::to_value(MemeticParams::default()),
        Algorithm::Nsga2 => serde_json::to_value(params.ga()),
        Algorithm::WeightedSum => serde_json::to_value(WeightedSumParams {
            ga: params.ga(),
            ..WeightedSumParams::default()
        }),
        Algorithm::GreedyInsertion => serde_json::to_value(GreedyParams::default()),
        Algorithm::Decimation => serde_json::to_value(DecimationParams::default()),
    };
    value.unwrap_or(serde_json::Value::Null)
}

/// Builds `algorithm` on `hf`. Fails with a message for the user when the parameters are out
/// of range.
pub fn build(
    algorithm: Algorithm,
    params: &Params,
    hf: Arc<Heightfield>,
) -> Result<Box<dyn Running>, String> {
    params.validate()?;
    Ok(match algorithm {
        Algorithm::Memetic => Box::new(
            Memetic::new(hf, MemeticParams::default(), params.seed).map_err(|e| e.to_string())?,
        ),
        Algorithm::Nsga2 => {
            Box::new(Nsga2::new(hf, params.ga(), params.seed).map_err(|e| e.to_string())?)
        }
        Algorithm::WeightedSum => {
            let p = WeightedSumParams {
                ga: params.ga(),
                ..WeightedSumParams::default()
            };
            Box::new(WeightedSum::new(hf, p, params.seed).map_err(|e| e.to_string())?)
        }
        Algorithm::GreedyInsertion => {
            Box::new(GreedyInsertion::new(hf, GreedyParams::default()).map_err(|e| e.to_string())?)
        }
        Algorithm::Decimation => Box::new(
            EdgeDecimation::new(hf, DecimationParams::default()).map_err(|e| e.to_string())?,
        ),
    })
}
