//! The methods the experiment compares: each method of the [`catalogue`](crate::catalogue),
//! and the memetic method's ablation variants (a component switched off), by the names the
//! command line and results.json use.
//!
//! A new method is added to the catalogue only; nothing in the experiment names methods one
//! by one.

use crate::catalogue::{Ablation, Algorithm, BudgetKind as CatalogueBudget, Component};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// One of the compared methods: a catalogue method, or one of its ablation variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Method {
    /// The catalogue method.
    pub algorithm: Algorithm,
    /// The component the variant switches off (`None`: the method itself).
    pub without: Option<Component>,
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
    /// NSGA-II with orthogonal-array crossover.
    pub const NSGA2: Method = Method::of(Algorithm::Nsga2);
    /// The weighted-sum GA.
    pub const WEIGHTED: Method = Method::of(Algorithm::Weighted);
    /// Edge decimation.
    #[cfg(test)]
    pub(crate) const DECIMATION: Method = Method::of(Algorithm::Decimation);
    /// Greedy insertion.
    pub const GREEDY: Method = Method::of(Algorithm::Greedy);
    /// The memetic method.
    pub const MEMETIC: Method = Method::of(Algorithm::Memetic);
    /// The memetic method without greedy seeding.
    pub const MEMETIC_NO_SEED: Method = Method::ablation(Component::GreedySeeding);
    /// The memetic method without its local search.
    #[cfg(test)]
    pub(crate) const MEMETIC_NO_LOCAL_SEARCH: Method = Method::ablation(Component::LocalSearch);

    /// The catalogue method `algorithm` itself.
    pub(crate) const fn of(algorithm: Algorithm) -> Method {
        Method {
            algorithm,
            without: None,
        }
    }

    const fn ablation(without: Component) -> Method {
        Method {
            algorithm: Algorithm::Memetic,
            without: Some(without),
        }
    }

    /// Every method and ablation variant, in the order the tables list them: the catalogue's
    /// methods, then each one's variants.
    pub(crate) fn all() -> Vec<Method> {
        let variants = Algorithm::ALL.into_iter().flat_map(|a| {
            a.spec().ablations.iter().map(move |v| Method {
                algorithm: a,
                without: Some(v.without),
            })
        });
        Method::standard().into_iter().chain(variants).collect()
    }

    /// The methods an experiment compares when none are named: every method in its own right
    /// (the ablation variants only run when asked for).
    pub fn standard() -> Vec<Method> {
        Algorithm::ALL.into_iter().map(Method::of).collect()
    }

    /// `self` followed by each of its ablation variants, in table order (just `self` for a
    /// method without variants).
    pub fn with_ablations(self) -> Vec<Method> {
        std::iter::once(self)
            .chain(
                Method::all()
                    .into_iter()
                    .filter(|m| m.spec().ablation.is_some_and(|(full, _)| full == self)),
            )
            .collect()
    }

    /// The variant's row in the catalogue, for an ablation variant.
    fn variant(self) -> Option<&'static Ablation> {
        let without = self.without?;
        self.algorithm
            .spec()
            .ablations
            .iter()
            .find(|v| v.without == without)
    }

    /// The method's fixed facts.
    pub fn spec(self) -> MethodSpec {
        let s = self.algorithm.spec();
        let budget = match s.budget {
            CatalogueBudget::OwnRule => BudgetKind::OwnRule,
            CatalogueBudget::Evaluations | CatalogueBudget::Generations => BudgetKind::Ga,
        };
        let base = MethodSpec {
            name: s.name,
            label: s.label,
            stochastic: s.stochastic,
            budget,
            colour: s.colour,
            cost: s.cost,
            ablation: None,
        };
        match self.variant() {
            Some(v) => MethodSpec {
                name: v.name,
                label: v.label,
                colour: v.colour,
                ablation: Some((Method::of(self.algorithm), v.removes)),
                ..base
            },
            None => base,
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
        let all = Method::all();
        all.iter()
            .copied()
            .find(|m| m.name() == name.trim())
            .ok_or_else(|| {
                format!(
                    "unknown method {name:?}; the methods are {}",
                    all.iter().map(|m| m.name()).collect::<Vec<_>>().join(", ")
                )
            })
    }
}

impl From<Algorithm> for Method {
    fn from(algorithm: Algorithm) -> Method {
        Method::of(algorithm)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Method {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Method {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Method, D::Error> {
        let name = String::deserialize(d)?;
        Method::parse(&name).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for m in Method::all() {
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
            Method::MEMETIC.with_ablations().len(),
            5,
            "the full method and four variants"
        );
        assert_eq!(Method::NSGA2.with_ablations(), vec![Method::NSGA2]);
    }

    #[test]
    fn names_labels_and_colours_are_distinct() {
        let all = Method::all();
        for (i, a) in all.iter().enumerate() {
            for b in &all[..i] {
                let (sa, sb) = (a.spec(), b.spec());
                assert!(sa.name != sb.name && sa.label != sb.label && sa.colour != sb.colour);
            }
        }
    }
}
