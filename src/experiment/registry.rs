//! The experiment's side of the [`catalogue`](crate::catalogue): a method, the experiment's
//! settings and a seed → a ready optimizer, the parameters it runs with (written to
//! results.json), and its budget in words for the report.
//!
//! Each method runs with its own defaults (the paper's settings) except the budget: a
//! generational GA takes [`Settings::population`] and either [`Settings::generations`]
//! ([`Budget::PerWeight`]) or an evaluation cap with no generation limit ([`Budget::Equal`]);
//! a method that runs to an evaluation budget takes the same evaluations; a method with its own
//! stopping rule takes nothing. So a method added to the catalogue runs at the same cost as the
//! others without a line here.

use super::ExperimentError;
use super::method::{BudgetKind, Method};
use super::settings::{Budget, DEFAULT_EQUAL_EVALUATIONS, Settings};
use crate::catalogue::{Algorithm, BudgetKind as CatalogueBudget, Params, Running};
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// The generation limit of a GA under [`Budget::Equal`]: never reached (each generation costs
/// at least one evaluation), and small enough for a 32-bit `usize` in results.json.
pub(crate) const UNLIMITED_GENERATIONS: usize = u32::MAX as usize;

/// The evaluations of one run of a method with an evaluation budget under
/// [`Budget::PerWeight`], where the GAs run for generations rather than evaluations: what an
/// NSGA-II run of the settings' population and generations spends, counted at
/// [`DEFAULT_EQUAL_EVALUATIONS`] for the paper's 100 × 50 (17 401 on jacksboro_65x65) and in
/// proportion to population × generations otherwise.
pub(crate) fn nsga2_equivalent_evaluations(settings: &Settings) -> u64 {
    let paper = (PAPER_POPULATION * PAPER_GENERATIONS) as u128;
    let asked = (settings.population as u128) * (settings.generations as u128);
    ((DEFAULT_EQUAL_EVALUATIONS as u128 * asked + paper / 2) / paper).max(1) as u64
}

/// The paper's population and generations, the scale of [`DEFAULT_EQUAL_EVALUATIONS`].
const PAPER_POPULATION: usize = 100;
const PAPER_GENERATIONS: usize = 50;

/// The catalogue parameters `method` runs with under `settings`: its budget, and for an
/// ablation variant the component it switches off.
pub(crate) fn catalogue_params(method: Method, settings: &Settings) -> Params {
    let mut p = Params {
        without: method.without,
        ..Params::default()
    };
    match method.algorithm.spec().budget {
        CatalogueBudget::Generations => {
            p.population = Some(settings.population);
            match settings.budget {
                Budget::PerWeight => p.generations = Some(settings.generations),
                Budget::Equal { evaluations } => {
                    p.generations = Some(UNLIMITED_GENERATIONS);
                    p.max_evaluations = Some(evaluations);
                }
            }
        }
        CatalogueBudget::Evaluations => {
            p.max_evaluations = Some(match settings.budget {
                Budget::Equal { evaluations } => evaluations,
                Budget::PerWeight => nsga2_equivalent_evaluations(settings),
            });
        }
        CatalogueBudget::OwnRule => {}
    }
    p
}

/// Is `method` the memetic method or one of its ablation variants?
pub(crate) fn is_memetic(method: Method) -> bool {
    method.algorithm == Algorithm::Memetic
}

/// How many GA runs one run of `method` is made of (the weighted-sum GA: one per weight), and
/// so how many shares an equal budget is split into. 1 for every other method.
pub(crate) fn ga_runs_per_run(method: Method) -> usize {
    method.algorithm.runs_per_run()
}

/// The budget of one run of `method` under `settings`, in words and evaluations, for the
/// report's Runs table.
pub(crate) fn budget_text(method: Method, settings: &Settings) -> String {
    if method.spec().budget == BudgetKind::OwnRule {
        return "own stopping rule".to_string();
    }
    let parts = ga_runs_per_run(method);
    let evaluation_budget = method.algorithm.spec().budget == CatalogueBudget::Evaluations;
    if evaluation_budget && settings.budget == Budget::PerWeight {
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
pub(crate) fn params(
    method: Method,
    settings: &Settings,
) -> Result<serde_json::Value, ExperimentError> {
    method
        .algorithm
        .configure(&catalogue_params(method, settings))
        .map(|c| c.json())
        .map_err(|message| ExperimentError::Params { method, message })
}

/// A fresh optimizer for `method` on `hf`. `seed` is used by stochastic methods (and must be
/// `Some` for them); deterministic methods ignore it.
///
/// Errors: [`ExperimentError::Params`] when the method refuses its parameters (e.g. a
/// population under 2), or a stochastic method gets no seed.
pub(crate) fn build(
    method: Method,
    settings: &Settings,
    hf: Arc<Heightfield>,
    seed: Option<u64>,
) -> Result<Box<dyn Running>, ExperimentError> {
    let refused = |message: String| ExperimentError::Params { method, message };
    let seed = match seed {
        Some(seed) => seed,
        None if method.is_stochastic() => {
            return Err(refused("a stochastic method needs a seed".into()));
        }
        None => 0,
    };
    method
        .algorithm
        .build(hf, &catalogue_params(method, settings), seed)
        .map(|built| built.optimizer)
        .map_err(refused)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_budgets_cap_every_ga_and_lift_the_generation_limit() {
        let equal = Settings::default();
        let p = params(Method::NSGA2, &equal).unwrap();
        assert_eq!(p["max_evaluations"], 17_400);
        assert_eq!(p["generations"], UNLIMITED_GENERATIONS as u64);
        let w = params(Method::WEIGHTED, &equal).unwrap();
        assert_eq!(w["max_evaluations"], 17_400);
        assert_eq!(w["weights"].as_array().unwrap().len(), 11);
        assert_eq!(
            budget_text(Method::WEIGHTED, &equal),
            "17400 = 11 weights × 1581 (+ 9 unspent)"
        );
        assert_eq!(budget_text(Method::GREEDY, &equal), "own stopping rule");
        let m = params(Method::MEMETIC, &equal).unwrap();
        assert_eq!(m["max_evaluations"], 17_400);
        assert_eq!(
            m.get("local_search"),
            None,
            "the full method writes no switch"
        );
        let v = params(Method::MEMETIC_NO_LOCAL_SEARCH, &equal).unwrap();
        assert_eq!(v["local_search"], false);
        assert_eq!(budget_text(Method::MEMETIC, &equal), "17400");

        let paper = Settings {
            budget: Budget::PerWeight,
            ..Settings::default()
        };
        let p = params(Method::NSGA2, &paper).unwrap();
        assert_eq!(p["max_evaluations"], serde_json::Value::Null);
        assert_eq!(p["generations"], 50);
        assert_eq!(
            budget_text(Method::WEIGHTED, &paper),
            "11 weights × (population 100 × 50 generations)"
        );
        assert_eq!(
            params(Method::MEMETIC, &paper).unwrap()["max_evaluations"],
            17_400
        );
        let half = Settings {
            generations: 25,
            ..paper
        };
        assert_eq!(nsga2_equivalent_evaluations(&half), 8_700);
    }
}
