//! What an experiment runs: the methods, the number of runs, the seed, the GA budget and the
//! reference point. The registry, the protocol and results.json all read it; it reads only the
//! methods.

use super::ExperimentError;
use super::method::Method;
use crate::metrics::DEFAULT_REFERENCE_POINT;
use serde::{Deserialize, Serialize};

/// The evaluations of one GA run under [`Budget::Equal`] by default: about what NSGA-II spends
/// in the paper's 50 generations of 100 individuals (17 401 on jacksboro_65x65).
pub const DEFAULT_EQUAL_EVALUATIONS: u64 = 17_400;

/// How much work each GA run may do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Budget {
    /// Every GA run gets `evaluations` evaluations, whatever the method: it runs with no
    /// generation limit and stops at the first mating boundary at or after them (so it may
    /// overshoot by less than one mating). The weighted-sum GA gives each of its W weights
    /// ⌊evaluations / W⌋ evaluations in the same way; the remainder (evaluations mod W) is not
    /// spent.
    Equal {
        /// The evaluations of one GA run.
        evaluations: u64,
    },
    /// The paper's budget: every GA run has [`Settings::population`] individuals for
    /// [`Settings::generations`] generations, and so does each weight of the weighted-sum GA.
    PerWeight,
}

impl Budget {
    /// What a results.json that names no budget was run with: the paper's per-weight budget.
    fn per_weight() -> Budget {
        Budget::PerWeight
    }
}

/// What to run: the methods, the number of runs, the seed, the GA budget, the reference point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// The methods to compare, in table order, each at most once.
    pub methods: Vec<Method>,
    /// Runs of NSGA-II and of each memetic method. Paper (NSGA-II): 10.
    pub runs: usize,
    /// Runs of the weighted-sum GA, each a sweep over its 11 weights. Paper: 1 (with
    /// per-weight budgets a sweep costs about 11 NSGA-II runs); at equal budgets a sweep costs
    /// one NSGA-II run, so it gets as many runs as NSGA-II by default.
    pub weighted_runs: usize,
    /// Run k of a stochastic method uses seed `seed + k`; also seeds the trade-off picks.
    pub seed: u64,
    /// GA population (NSGA-II and each weighted-sum run). Paper: 100.
    pub population: usize,
    /// GA generations under [`Budget::PerWeight`]. Paper: 50.
    pub generations: usize,
    /// How many evaluations each GA run may spend.
    #[serde(default = "Budget::per_weight")]
    pub budget: Budget,
    /// The hypervolume reference point in normalised (E, T). Default (1.1, 1.1).
    pub reference_point: [f64; 2],
}

impl Default for Settings {
    /// The paper's settings at equal budgets: every standard method ([`Method::standard`]; the
    /// ablation variants run only when named), 10 runs of each GA, seed 1,
    /// population 100, [`DEFAULT_EQUAL_EVALUATIONS`] per GA run (50 generations under
    /// [`Budget::PerWeight`]), reference point (1.1, 1.1).
    fn default() -> Self {
        Settings {
            methods: Method::standard(),
            runs: 10,
            weighted_runs: 10,
            seed: 1,
            population: 100,
            generations: 50,
            budget: Budget::Equal {
                evaluations: DEFAULT_EQUAL_EVALUATIONS,
            },
            reference_point: DEFAULT_REFERENCE_POINT,
        }
    }
}

impl Settings {
    /// Checks the settings that do not depend on a method's own parameter checks.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        let bad = |m: &str| Err(ExperimentError::Settings(m.to_string()));
        if self.methods.is_empty() {
            return bad("at least one method is needed");
        }
        for (i, m) in self.methods.iter().enumerate() {
            if self.methods[..i].contains(m) {
                return bad(&format!("method {m} is listed twice"));
            }
        }
        if self.runs == 0 || self.weighted_runs == 0 {
            return bad("the number of runs must be at least 1");
        }
        if let Budget::Equal { evaluations } = self.budget {
            let least = self
                .methods
                .iter()
                .map(|m| m.algorithm.runs_per_run())
                .max()
                .unwrap_or(1) as u64;
            if evaluations < least {
                return bad(&format!(
                    "an equal budget of {evaluations} evaluations is too small: the weighted-sum GA shares it between its {least} weights, so at least {least} are needed"
                ));
            }
        }
        if !self
            .reference_point
            .iter()
            .all(|v| v.is_finite() && *v > 0.0)
        {
            return bad(&format!(
                "the reference point must be two positive finite numbers (normalised E and T), got {:?}",
                self.reference_point
            ));
        }
        Ok(())
    }

    /// How many runs `method` gets: [`Settings::runs`] for NSGA-II,
    /// [`Settings::weighted_runs`] for the weighted-sum GA, 1 for a deterministic method.
    pub(crate) fn runs_of(&self, method: Method) -> usize {
        if !method.is_stochastic() {
            1
        } else if method == Method::WEIGHTED {
            self.weighted_runs
        } else {
            // NSGA-II, the memetic method and its variants: run k with seed `seed + k`.
            self.runs
        }
    }
}
