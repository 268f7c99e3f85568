//! The methods the experiment compares, by the names the command line uses, with everything
//! the tables, the figure and the scheduler need to know about each.
//!
//! A new method (or a variant of one) is added here — a variant of [`Method`] and its row in
//! [`Method::spec`] — and in [`registry`](super::registry), which builds it; nothing else in
//! the experiment names methods one by one.

use serde::{Deserialize, Serialize};
use std::fmt;

/// One of the compared methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// NSGA-II with orthogonal-array crossover (stochastic).
    Nsga2,
    /// The weighted-sum GA, one GA run per weight w = 0, 0.1, …, 1 (stochastic).
    Weighted,
    /// Edge decimation at 5 %, 10 %, …, 50 % reduction (deterministic).
    Decimation,
    /// Greedy insertion (deterministic).
    Greedy,
}

/// What kind of budget a method runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BudgetKind {
    /// A genetic algorithm: it spends the experiment's GA budget (see
    /// [`Budget`](super::Budget)).
    Ga,
    /// A method that stops by its own rule (a list of reductions, or every point inserted).
    OwnRule,
}

/// The fixed facts about one method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MethodSpec {
    /// The command-line name.
    pub name: &'static str,
    /// The name the tables and the figure show.
    pub label: &'static str,
    /// Whether it draws random numbers (repeated runs with different seeds differ);
    /// deterministic methods are run once.
    pub stochastic: bool,
    /// How its budget is set.
    pub budget: BudgetKind,
    /// Its colour in the fronts figure.
    pub colour: &'static str,
    /// Rough cost of one run, larger first in the scheduler (so the last jobs are short).
    pub cost: u8,
}

impl Method {
    /// Every method, in the order the tables list them.
    pub const ALL: [Method; 4] = [
        Method::Nsga2,
        Method::Weighted,
        Method::Decimation,
        Method::Greedy,
    ];

    /// The method's fixed facts (colours: the colour-blind-safe Okabe–Ito hues).
    pub fn spec(self) -> MethodSpec {
        match self {
            Method::Nsga2 => MethodSpec {
                name: "nsga2",
                label: "NSGA-II",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#D55E00",
                cost: 2,
            },
            Method::Weighted => MethodSpec {
                name: "weighted",
                label: "Weighted-sum GA",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#0072B2",
                cost: 3,
            },
            Method::Decimation => MethodSpec {
                name: "decimation",
                label: "Decimation",
                stochastic: false,
                budget: BudgetKind::OwnRule,
                colour: "#009E73",
                cost: 0,
            },
            Method::Greedy => MethodSpec {
                name: "greedy",
                label: "Greedy insertion",
                stochastic: false,
                budget: BudgetKind::OwnRule,
                colour: "#CC79A7",
                cost: 1,
            },
        }
    }

    /// The command-line name (`nsga2`, `weighted`, `decimation`, `greedy`).
    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// The name the tables and the figure show.
    pub fn label(self) -> &'static str {
        self.spec().label
    }

    /// Whether the method draws random numbers, so that repeated runs with different seeds
    /// differ. Deterministic methods are run once.
    pub fn is_stochastic(self) -> bool {
        self.spec().stochastic
    }

    /// Whether the method spends the experiment's GA budget.
    pub fn is_ga(self) -> bool {
        self.spec().budget == BudgetKind::Ga
    }

    /// Parses a command-line name; the error lists the valid ones.
    pub fn parse(name: &str) -> Result<Method, String> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == name.trim())
            .ok_or_else(|| {
                format!(
                    "unknown method {name:?}; the methods are {}",
                    Method::ALL.map(Method::name).join(", ")
                )
            })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for m in Method::ALL {
            assert_eq!(Method::parse(m.name()), Ok(m));
            assert_eq!(
                serde_json::to_string(&m).unwrap(),
                format!("\"{}\"", m.name())
            );
        }
        let err = Method::parse("nsga3").unwrap_err();
        assert!(err.contains("nsga2, weighted, decimation, greedy"), "{err}");
    }

    #[test]
    fn names_labels_and_colours_are_distinct() {
        for (i, a) in Method::ALL.iter().enumerate() {
            for b in &Method::ALL[..i] {
                let (sa, sb) = (a.spec(), b.spec());
                assert!(sa.name != sb.name && sa.label != sb.label && sa.colour != sb.colour);
            }
        }
    }
}
