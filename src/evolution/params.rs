//! Parameters of the genetic algorithms, with the paper's defaults. They are serialised into
//! front.json (and share links), so every field has a stable name.

use super::oax::DEFAULT_FACTORS;
use super::operators::{CrossoverKind, free_genes};
use crate::heightfield::Heightfield;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Parameters shared by NSGA-II and each run of the weighted-sum GA.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct GaParams {
    /// Population size μ (also the number of offspring λ per generation). Paper: 100.
    pub population: usize,
    /// Generations after the initial population. Paper: 50.
    pub generations: usize,
    /// Probability that a mating uses crossover (else the parents are copied). Paper: 0.8.
    pub crossover_probability: f64,
    /// Bit-flip probability per free gene; `None` = 1/L with L = N − 4 (paper).
    pub mutation_probability: Option<f64>,
    /// The crossover operator. Paper: orthogonal-array crossover.
    pub crossover: CrossoverKind,
    /// Number of OAX factors F (array L_M with M the smallest power of two > F).
    pub factors: usize,
    /// Stop once this many evaluations were spent (checked between units of work).
    pub max_evaluations: Option<u64>,
    /// Fraction of the initial population NSGA-II seeds from greedy insertion, in [0, 1]:
    /// ⌊fraction · population⌋ individuals (see `super::nsga2`). 0 (the default, and the paper's
    /// setting) seeds nothing. The weighted-sum GA refuses values above 0.
    pub greedy_seed_fraction: f64,
}

impl Default for GaParams {
    fn default() -> Self {
        Self {
            population: 100,
            generations: 50,
            crossover_probability: 0.8,
            mutation_probability: None,
            crossover: CrossoverKind::Oax,
            factors: DEFAULT_FACTORS,
            max_evaluations: None,
            greedy_seed_fraction: 0.0,
        }
    }
}

/// Why a set of parameters cannot run.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamsError {
    /// The population is smaller than 2 (a mating needs two parents).
    PopulationTooSmall(usize),
    /// A probability is not in [0, 1].
    BadProbability { name: &'static str, value: f64 },
    /// F is 0, 1 (nothing to recombine) or over 63 (the array would have 2^6+ rows per child).
    BadFactors(usize),
    /// A weight of the weighted-sum GA is not in [0, 1], or there is none.
    BadWeights,
    /// The greedy seed fraction is not in [0, 1].
    BadSeedFraction(f64),
    /// Greedy seeding was asked of an algorithm that does not offer it (the weighted-sum GA).
    SeedingUnsupported,
}

impl fmt::Display for ParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::PopulationTooSmall(n) => {
                write!(
                    f,
                    "the population must have at least 2 individuals, got {n}"
                )
            }
            Self::BadProbability { name, value } => {
                write!(f, "the {name} must be between 0 and 1, got {value}")
            }
            Self::BadFactors(n) => write!(
                f,
                "the number of crossover factors must be between 2 and 63, got {n}"
            ),
            Self::BadWeights => write!(
                f,
                "the weighted-sum GA needs at least one weight, each between 0 and 1"
            ),
            Self::BadSeedFraction(x) => write!(
                f,
                "the greedy seed fraction must be between 0 and 1, got {x}"
            ),
            Self::SeedingUnsupported => write!(
                f,
                "seeding from greedy insertion is offered for NSGA-II only, not the weighted-sum GA"
            ),
        }
    }
}

impl std::error::Error for ParamsError {}

impl GaParams {
    /// Checks the parameters.
    pub(crate) fn validate(&self) -> Result<(), ParamsError> {
        if self.population < 2 {
            return Err(ParamsError::PopulationTooSmall(self.population));
        }
        let probability = |name, value: f64| {
            if (0.0..=1.0).contains(&value) {
                Ok(())
            } else {
                Err(ParamsError::BadProbability { name, value })
            }
        };
        probability("crossover probability", self.crossover_probability)?;
        if let Some(p) = self.mutation_probability {
            probability("mutation probability", p)?;
        }
        if !(2..=63).contains(&self.factors) {
            return Err(ParamsError::BadFactors(self.factors));
        }
        // Written so that NaN fails too.
        if !(0.0..=1.0).contains(&self.greedy_seed_fraction) {
            return Err(ParamsError::BadSeedFraction(self.greedy_seed_fraction));
        }
        Ok(())
    }

    /// The number of initial individuals seeded from greedy insertion: ⌊fraction · population⌋.
    pub(crate) fn greedy_seeds(&self) -> usize {
        (self.greedy_seed_fraction * self.population as f64).floor() as usize
    }

    /// The mutation probability on `hf`: the given one, else 1/L.
    pub(crate) fn mutation_on(&self, hf: &Heightfield) -> f64 {
        self.mutation_probability
            .unwrap_or(1.0 / free_genes(hf) as f64)
    }
}
