//! The parameter form of the app (the source paper's defaults) and how it fills the
//! [`catalogue`](crate::catalogue)'s parameters; the methods themselves are the catalogue's.

use crate::catalogue::{BudgetKind, Param, Params as CatalogueParams};
use crate::evolution::{CrossoverKind, GaParams};
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

pub use crate::catalogue::{Algorithm, Running};

/// True when [`build`] reads `field` of the form for `algorithm`: the seed for a stochastic
/// method; the GA fields for a generational GA that reads them. A method with an evaluation
/// budget (memetic) keeps its own population and budget, and a method with its own stopping
/// rule reads nothing.
pub fn uses(algorithm: Algorithm, field: Field) -> bool {
    let spec = algorithm.spec();
    match field.param() {
        None => spec.stochastic,
        Some(param) => spec.budget == BudgetKind::Generations && algorithm.reads(param),
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

    /// The catalogue parameter the field sets (`None` for the seed, which is not one).
    pub fn param(self) -> Option<Param> {
        match self {
            Field::Population => Some(Param::Population),
            Field::Generations => Some(Param::Generations),
            Field::Crossover => Some(Param::Crossover),
            Field::CrossoverProbability => Some(Param::CrossoverProbability),
            Field::MutationProbability => Some(Param::MutationProbability),
            Field::Seed => None,
        }
    }

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
    /// The error the front minimises beside T (the page's error menu); a method that does not
    /// support it refuses the run. Written only when not `sum`, so links made before it
    /// existed read as sum and a sum link reads as before.
    #[serde(default, skip_serializing_if = "ErrorMeasure::is_sum")]
    pub error: ErrorMeasure,
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
            error: ErrorMeasure::Sum,
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

/// The catalogue parameters the form sets for `algorithm`: the fields it [`uses`].
fn catalogue_params(algorithm: Algorithm, params: &Params) -> CatalogueParams {
    let set = |field: Field| uses(algorithm, field);
    CatalogueParams {
        population: set(Field::Population).then_some(params.population),
        generations: set(Field::Generations).then_some(params.generations),
        crossover: set(Field::Crossover).then_some(params.crossover),
        crossover_probability: set(Field::CrossoverProbability)
            .then_some(params.crossover_probability),
        mutation_probability: if set(Field::MutationProbability) {
            params.mutation_probability
        } else {
            None
        },
        error: params.error,
        ..CatalogueParams::default()
    }
}

/// The parameters as front.json records them (the same JSON as `paretomesh run --out`).
pub fn params_json(algorithm: Algorithm, params: &Params) -> serde_json::Value {
    algorithm
        .configure(&catalogue_params(algorithm, params))
        .map_or(serde_json::Value::Null, |c| c.json())
}

/// Builds `algorithm` on `hf`. Fails with a message for the user when the parameters are out
/// of range.
pub fn build(
    algorithm: Algorithm,
    params: &Params,
    hf: Arc<Heightfield>,
) -> Result<Box<dyn Running>, String> {
    params.validate()?;
    Ok(algorithm
        .build(hf, &catalogue_params(algorithm, params), params.seed)?
        .optimizer)
}
