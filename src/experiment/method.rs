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
    /// The memetic NSGA-II, the project's own method (stochastic).
    Memetic,
    /// The memetic method without greedy seeding: random kept sets at log-spaced densities.
    #[serde(rename = "memetic-no-seed")]
    MemeticNoSeed,
    /// The memetic method with random bit-flip mutation instead of the error-guided operators.
    #[serde(rename = "memetic-random-mutation")]
    MemeticRandomMutation,
    /// The memetic method mating with any member instead of a neighbour in T.
    #[serde(rename = "memetic-no-neighbour-mating")]
    MemeticNoNeighbourMating,
    /// The memetic method without its local search.
    #[serde(rename = "memetic-no-local-search")]
    MemeticNoLocalSearch,
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
    /// For an ablation variant: the full method, and what the variant removes from it (in the
    /// report's words). `None` for a method in its own right.
    pub ablation: Option<(Method, &'static str)>,
}

impl Method {
    /// Every method and ablation variant, in the order the tables list them.
    pub const ALL: [Method; 9] = [
        Method::Nsga2,
        Method::Weighted,
        Method::Decimation,
        Method::Greedy,
        Method::Memetic,
        Method::MemeticNoSeed,
        Method::MemeticRandomMutation,
        Method::MemeticNoNeighbourMating,
        Method::MemeticNoLocalSearch,
    ];

    /// The methods an experiment compares when none are named: every method in its own right
    /// (the ablation variants only run when asked for).
    pub const STANDARD: [Method; 5] = [
        Method::Nsga2,
        Method::Weighted,
        Method::Decimation,
        Method::Greedy,
        Method::Memetic,
    ];

    /// `self` followed by each of its ablation variants, in table order (just `self` for a
    /// method without variants).
    pub fn with_ablations(self) -> Vec<Method> {
        std::iter::once(self)
            .chain(
                Method::ALL
                    .into_iter()
                    .filter(|m| m.spec().ablation.is_some_and(|(full, _)| full == self)),
            )
            .collect()
    }

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
                ablation: None,
            },
            Method::Weighted => MethodSpec {
                name: "weighted",
                label: "Weighted-sum GA",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#0072B2",
                cost: 3,
                ablation: None,
            },
            Method::Decimation => MethodSpec {
                name: "decimation",
                label: "Decimation",
                stochastic: false,
                budget: BudgetKind::OwnRule,
                colour: "#009E73",
                cost: 0,
                ablation: None,
            },
            Method::Greedy => MethodSpec {
                name: "greedy",
                label: "Greedy insertion",
                stochastic: false,
                budget: BudgetKind::OwnRule,
                colour: "#CC79A7",
                cost: 1,
                ablation: None,
            },
            Method::Memetic => MethodSpec {
                name: "memetic",
                label: "Memetic",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#000000",
                cost: 2,
                ablation: None,
            },
            Method::MemeticNoSeed => MethodSpec {
                name: "memetic-no-seed",
                label: "Memetic, no greedy seeding",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#E69F00",
                cost: 2,
                ablation: Some((
                    Method::Memetic,
                    "greedy seeding: the initial population is random kept sets at log-spaced densities instead of greedy-insertion snapshots, and the greedy fronts do not start the archive",
                )),
            },
            Method::MemeticRandomMutation => MethodSpec {
                name: "memetic-random-mutation",
                label: "Memetic, random mutation",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#56B4E9",
                cost: 2,
                ablation: Some((
                    Method::Memetic,
                    "error-guided mutation: a child flips one random grid point in or out instead of an error-guided insertion, removal or vertex move",
                )),
            },
            Method::MemeticNoNeighbourMating => MethodSpec {
                name: "memetic-no-neighbour-mating",
                label: "Memetic, random mates",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#999999",
                cost: 2,
                ablation: Some((
                    Method::Memetic,
                    "mating among neighbours: a crossover mate is any other member, whatever its T, instead of one of the 4 nearest in T",
                )),
            },
            Method::MemeticNoLocalSearch => MethodSpec {
                name: "memetic-no-local-search",
                label: "Memetic, no local search",
                stochastic: true,
                budget: BudgetKind::Ga,
                colour: "#F0E442",
                cost: 2,
                ablation: Some((
                    Method::Memetic,
                    "local search: no fixed-T swap moves on archive members; the budget goes to offspring only",
                )),
            },
        }
    }

    /// The command-line name (`nsga2`, `weighted`, `decimation`, `greedy`, `memetic`, …).
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
        assert!(
            err.contains("nsga2, weighted, decimation, greedy, memetic, memetic-no-seed"),
            "{err}"
        );
        assert_eq!(
            Method::Memetic.with_ablations().len(),
            5,
            "the full method and four variants"
        );
        assert_eq!(Method::Nsga2.with_ablations(), vec![Method::Nsga2]);
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
