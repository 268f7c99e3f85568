//! The method registry: a method name, the experiment's settings and a seed → a ready
//! [`Optimizer`], the parameters it runs with (written to results.json), and its budget in
//! words for the report.
//!
//! Each method runs with its own crate defaults (the paper's settings) except the GA budget,
//! which every GA takes from [`ga_params`]: [`Settings::population`], and either
//! [`Settings::generations`] ([`Budget::PerWeight`]) or an evaluation cap with no generation
//! limit ([`Budget::Equal`]). A GA added here must take its budget from [`ga_params`] too, so
//! that it runs at the same cost as the others.

use super::ExperimentError;
use super::method::{BudgetKind, Method};
use super::protocol::{Budget, DEFAULT_EQUAL_EVALUATIONS, Settings};
use crate::baselines::{DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams};
use crate::evolution::memetic::{Memetic, MemeticParams};
use crate::evolution::{GaParams, Nsga2, WeightedSum, WeightedSumParams};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use std::sync::Arc;

/// The generation limit of a GA under [`Budget::Equal`]: never reached (each generation costs
/// at least one evaluation), and small enough for a 32-bit `usize` in results.json.
pub const UNLIMITED_GENERATIONS: usize = u32::MAX as usize;

/// The GA parameters every GA method starts from: the crate defaults with the experiment's
/// population and budget.
pub fn ga_params(settings: &Settings) -> GaParams {
    let paper = GaParams {
        population: settings.population,
        generations: settings.generations,
        ..GaParams::default()
    };
    match settings.budget {
        Budget::PerWeight => paper,
        Budget::Equal { evaluations } => GaParams {
            generations: UNLIMITED_GENERATIONS,
            max_evaluations: Some(evaluations),
            ..paper
        },
    }
}

fn weighted_params(settings: &Settings) -> WeightedSumParams {
    WeightedSumParams {
        ga: ga_params(settings),
        ..WeightedSumParams::default()
    }
}

/// The evaluations of one memetic run under [`Budget::PerWeight`], where the other GAs run
/// for generations rather than evaluations: what an NSGA-II run of the settings' population
/// and generations spends, counted at [`DEFAULT_EQUAL_EVALUATIONS`] for the paper's 100 × 50
/// (17 401 on jacksboro_65x65) and in proportion to population × generations otherwise.
pub fn nsga2_equivalent_evaluations(settings: &Settings) -> u64 {
    let paper = (PAPER_POPULATION * PAPER_GENERATIONS) as u128;
    let asked = (settings.population as u128) * (settings.generations as u128);
    ((DEFAULT_EQUAL_EVALUATIONS as u128 * asked + paper / 2) / paper).max(1) as u64
}

/// The paper's population and generations, the scale of [`DEFAULT_EQUAL_EVALUATIONS`].
const PAPER_POPULATION: usize = 100;
const PAPER_GENERATIONS: usize = 50;

/// The memetic method's parameters (its own defaults, population included) with the
/// experiment's evaluation budget and, for an ablation variant, its component switched off.
pub fn memetic_params(method: Method, settings: &Settings) -> MemeticParams {
    let evaluations = match settings.budget {
        Budget::Equal { evaluations } => evaluations,
        Budget::PerWeight => nsga2_equivalent_evaluations(settings),
    };
    let full = MemeticParams {
        max_evaluations: Some(evaluations),
        ..MemeticParams::default()
    };
    match method {
        Method::MemeticNoSeed => MemeticParams {
            greedy_seeding: false,
            ..full
        },
        Method::MemeticRandomMutation => MemeticParams {
            guided_mutation: false,
            ..full
        },
        Method::MemeticNoNeighbourMating => MemeticParams {
            neighbour_mating: false,
            ..full
        },
        Method::MemeticNoLocalSearch => MemeticParams {
            local_search: false,
            ..full
        },
        _ => full,
    }
}

/// Is `method` the memetic method or one of its ablation variants?
pub fn is_memetic(method: Method) -> bool {
    method == Method::Memetic
        || method
            .spec()
            .ablation
            .is_some_and(|(full, _)| full == Method::Memetic)
}

/// How many GA runs one run of `method` is made of (the weighted-sum GA: one per weight), and
/// so how many shares an equal budget is split into. 1 for every other method.
pub fn ga_runs_per_run(method: Method) -> usize {
    match method {
        Method::Weighted => WeightedSumParams::default().weights.len(),
        _ => 1,
    }
}

/// The budget of one run of `method` under `settings`, in words and evaluations, for the
/// report's Runs table.
pub fn budget_text(method: Method, settings: &Settings) -> String {
    if method.spec().budget == BudgetKind::OwnRule {
        return "own stopping rule".to_string();
    }
    let parts = ga_runs_per_run(method);
    if is_memetic(method) && settings.budget == Budget::PerWeight {
        return format!(
            "{} (NSGA-II's population {} × {} generations, in evaluations)",
            nsga2_equivalent_evaluations(settings),
            settings.population,
            settings.generations
        );
    }
    match settings.budget {
        Budget::Equal { evaluations } if parts > 1 => {
            let share = evaluations / parts as u64;
            format!(
                "{evaluations} = {parts} weights × {share} (+ {} unspent)",
                evaluations - share * parts as u64
            )
        }
        Budget::Equal { evaluations } => format!("{evaluations}"),
        Budget::PerWeight if parts > 1 => format!(
            "{parts} weights × (population {} × {} generations)",
            settings.population, settings.generations
        ),
        Budget::PerWeight => format!(
            "population {} × {} generations",
            settings.population, settings.generations
        ),
    }
}

/// The parameters `method` runs with under `settings`, as its params type serialises them.
pub fn params(method: Method, settings: &Settings) -> Result<serde_json::Value, ExperimentError> {
    let value = match method {
        Method::Nsga2 => serde_json::to_value(ga_params(settings)),
        Method::Weighted => serde_json::to_value(weighted_params(settings)),
        Method::Decimation => serde_json::to_value(DecimationParams::default()),
        Method::Greedy => serde_json::to_value(GreedyParams::default()),
        m => serde_json::to_value(memetic_params(m, settings)),
    };
    value.map_err(|e| ExperimentError::Params {
        method,
        message: e.to_string(),
    })
}

/// A fresh optimizer for `method` on `hf`. `seed` is used by stochastic methods (and must be
/// `Some` for them); deterministic methods ignore it.
///
/// Errors: [`ExperimentError::Params`] when the method refuses its parameters (e.g. a
/// population under 2), or a stochastic method gets no seed.
pub fn build(
    method: Method,
    settings: &Settings,
    hf: Arc<Heightfield>,
    seed: Option<u64>,
) -> Result<Box<dyn Optimizer + Send>, ExperimentError> {
    let refused = |message: String| ExperimentError::Params { method, message };
    let need_seed = || seed.ok_or_else(|| refused("a stochastic method needs a seed".into()));
    Ok(match method {
        Method::Nsga2 => Box::new(
            Nsga2::new(hf, ga_params(settings), need_seed()?)
                .map_err(|e| refused(e.to_string()))?,
        ),
        Method::Weighted => Box::new(
            WeightedSum::new(hf, weighted_params(settings), need_seed()?)
                .map_err(|e| refused(e.to_string()))?,
        ),
        Method::Decimation => Box::new(
            EdgeDecimation::new(hf, DecimationParams::default())
                .map_err(|e| refused(e.to_string()))?,
        ),
        Method::Greedy => Box::new(
            GreedyInsertion::new(hf, GreedyParams::default())
                .map_err(|e| refused(e.to_string()))?,
        ),
        m => Box::new(
            Memetic::new(hf, memetic_params(m, settings), need_seed()?)
                .map_err(|e| refused(e.to_string()))?,
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_budgets_cap_every_ga_and_lift_the_generation_limit() {
        let equal = Settings::default();
        let p = params(Method::Nsga2, &equal).unwrap();
        assert_eq!(p["max_evaluations"], 17_400);
        assert_eq!(p["generations"], UNLIMITED_GENERATIONS as u64);
        let w = params(Method::Weighted, &equal).unwrap();
        assert_eq!(w["max_evaluations"], 17_400);
        assert_eq!(w["weights"].as_array().unwrap().len(), 11);
        assert_eq!(
            budget_text(Method::Weighted, &equal),
            "17400 = 11 weights × 1581 (+ 9 unspent)"
        );
        assert_eq!(budget_text(Method::Greedy, &equal), "own stopping rule");
        let m = params(Method::Memetic, &equal).unwrap();
        assert_eq!(m["max_evaluations"], 17_400);
        assert_eq!(
            m.get("local_search"),
            None,
            "the full method writes no switch"
        );
        let v = params(Method::MemeticNoLocalSearch, &equal).unwrap();
        assert_eq!(v["local_search"], false);
        assert_eq!(budget_text(Method::Memetic, &equal), "17400");

        let paper = Settings {
            budget: Budget::PerWeight,
            ..Settings::default()
        };
        let p = params(Method::Nsga2, &paper).unwrap();
        assert_eq!(p["max_evaluations"], serde_json::Value::Null);
        assert_eq!(p["generations"], 50);
        assert_eq!(
            budget_text(Method::Weighted, &paper),
            "11 weights × (population 100 × 50 generations)"
        );
        assert_eq!(
            params(Method::Memetic, &paper).unwrap()["max_evaluations"],
            17_400
        );
        let half = Settings {
            generations: 25,
            ..paper
        };
        assert_eq!(nsga2_equivalent_evaluations(&half), 8_700);
    }
}
