//! The four methods the experiment compares, by the names the command line uses.

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

impl Method {
    /// Every method, in the order the tables list them.
    pub const ALL: [Method; 4] = [
        Method::Nsga2,
        Method::Weighted,
        Method::Decimation,
        Method::Greedy,
    ];

    /// The command-line name (`nsga2`, `weighted`, `decimation`, `greedy`).
    pub fn name(self) -> &'static str {
        match self {
            Method::Nsga2 => "nsga2",
            Method::Weighted => "weighted",
            Method::Decimation => "decimation",
            Method::Greedy => "greedy",
        }
    }

    /// The name the tables and the figure show.
    pub fn label(self) -> &'static str {
        match self {
            Method::Nsga2 => "NSGA-II",
            Method::Weighted => "Weighted-sum GA",
            Method::Decimation => "Decimation",
            Method::Greedy => "Greedy insertion",
        }
    }

    /// Whether the method draws random numbers, so that repeated runs with different seeds
    /// differ. Deterministic methods are run once.
    pub fn is_stochastic(self) -> bool {
        matches!(self, Method::Nsga2 | Method::Weighted)
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
}
