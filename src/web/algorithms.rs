//! The algorithms the app offers, their parameters (the source paper's defaults), and the one
//! place that builds an [`Optimizer`] from them. Each algorithm plugs in here as the core
//! provides it.

use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// An algorithm the app can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Algorithm {
    /// NSGA-II with the chosen crossover (the paper's method with orthogonal-array crossover).
    Nsga2,
    /// A GA on weighted sums of E and T, one run per weight.
    WeightedSum,
    /// Greedy insertion (Garland & Heckbert 1995).
    GreedyInsertion,
    /// Edge decimation.
    Decimation,
}

impl Algorithm {
    /// Every algorithm, in the order of the menu.
    pub const ALL: [Algorithm; 4] = [
        Algorithm::Nsga2,
        Algorithm::WeightedSum,
        Algorithm::GreedyInsertion,
        Algorithm::Decimation,
    ];

    /// The menu's value for this algorithm.
    pub fn key(self) -> &'static str {
        match self {
            Algorithm::Nsga2 => "nsga2",
            Algorithm::WeightedSum => "weighted-sum",
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
            Algorithm::Nsga2 => "NSGA-II",
            Algorithm::WeightedSum => "weighted-sum GA",
            Algorithm::GreedyInsertion => "greedy insertion",
            Algorithm::Decimation => "edge decimation",
        }
    }

    /// True when the GA parameters (population, crossover, mutation) apply.
    pub fn is_genetic(self) -> bool {
        matches!(self, Algorithm::Nsga2 | Algorithm::WeightedSum)
    }
}

/// The crossover operator of the GAs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum CrossoverKind {
    /// Orthogonal-array crossover (Huang & Ho 2003), the paper's operator.
    Orthogonal,
    /// Uniform crossover.
    Uniform,
}

impl CrossoverKind {
    /// The menu's value.
    pub fn key(self) -> &'static str {
        match self {
            CrossoverKind::Orthogonal => "oax",
            CrossoverKind::Uniform => "uniform",
        }
    }

    /// The kind with menu value `key`.
    pub fn from_key(key: &str) -> Option<CrossoverKind> {
        [CrossoverKind::Orthogonal, CrossoverKind::Uniform]
            .into_iter()
            .find(|k| k.key() == key)
    }
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
        Self {
            population: 100,
            generations: 50,
            crossover: CrossoverKind::Orthogonal,
            crossover_probability: 0.8,
            mutation_probability: None,
            seed: 1,
        }
    }
}

impl Params {
    /// Checks the ranges; the message says which field is wrong and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        if !(2..=10_000).contains(&self.population) {
            return Err(format!(
                "population must be between 2 and 10000, got {}",
                self.population
            ));
        }
        if !(1..=100_000).contains(&self.generations) {
            return Err(format!(
                "generations must be between 1 and 100000, got {}",
                self.generations
            ));
        }
        if !(0.0..=1.0).contains(&self.crossover_probability) {
            return Err(format!(
                "crossover probability must be between 0 and 1, got {}",
                self.crossover_probability
            ));
        }
        if let Some(p) = self.mutation_probability
            && !(0.0..=1.0).contains(&p)
        {
            return Err(format!(
                "mutation probability must be between 0 and 1, got {p}"
            ));
        }
        Ok(())
    }
}

/// Builds the optimizer for `algorithm` on `hf`. Fails with a message for the user when the
/// parameters are out of range or the algorithm is not part of this build.
pub fn build(
    algorithm: Algorithm,
    params: &Params,
    hf: Arc<Heightfield>,
) -> Result<Box<dyn Optimizer>, String> {
    params.validate()?;
    let _ = hf;
    Err(format!(
        "{} is not available in this build yet",
        algorithm.label()
    ))
}
