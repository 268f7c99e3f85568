//! The error measure a run optimises: the E of its (E, T) front.
//!
//! Every score records all three (E_sum, E_max and RMS) exactly; the measure only says which
//! one a front is Pareto-optimal in. `sum` is the paper's and the default.

use crate::evaluator::Score;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Which error a front minimises beside T.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(not(target_arch = "wasm32"), derive(clap::ValueEnum))]
pub enum ErrorMeasure {
    /// E_sum = Σ |z − z̃| over all grid points (the paper's).
    #[default]
    Sum,
    /// RMS = sqrt(Σ (z − z̃)² / N).
    Rms,
    /// E_max = max |z − z̃|, the vertical error bound terrain tools use.
    Max,
}

impl ErrorMeasure {
    /// Every measure, the default first.
    pub const ALL: [ErrorMeasure; 3] = [ErrorMeasure::Sum, ErrorMeasure::Rms, ErrorMeasure::Max];

    /// The name the CLI, front.json, share links and Python use.
    pub fn name(self) -> &'static str {
        match self {
            ErrorMeasure::Sum => "sum",
            ErrorMeasure::Rms => "rms",
            ErrorMeasure::Max => "max",
        }
    }

    /// The measure named `name`, if any.
    pub(crate) fn from_name(name: &str) -> Option<ErrorMeasure> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The measure named `name`, or an error that lists the known names.
    pub fn parse(name: &str) -> Result<ErrorMeasure, String> {
        Self::from_name(name).ok_or_else(|| {
            let known: Vec<&str> = Self::ALL.iter().map(|m| m.name()).collect();
            format!(
                "unknown error measure {name:?}: use one of {}",
                known.join(", ")
            )
        })
    }

    /// Is this the default measure (`sum`), which front.json leaves unrecorded?
    pub(crate) fn is_sum(&self) -> bool {
        *self == ErrorMeasure::Sum
    }

    /// The error of `score` in this measure.
    pub fn of(self, score: &Score) -> f64 {
        match self {
            ErrorMeasure::Sum => score.e_sum,
            ErrorMeasure::Rms => score.rms,
            ErrorMeasure::Max => score.e_max,
        }
    }

    /// The minimised objective vector (this error, T) of `score`.
    pub(crate) fn objectives(self, score: &Score) -> [f64; 2] {
        [self.of(score), score.t as f64]
    }

    /// The label of the error axis ("E_sum", "RMS", "E_max").
    pub fn label(self) -> &'static str {
        match self {
            ErrorMeasure::Sum => "E_sum",
            ErrorMeasure::Rms => "RMS",
            ErrorMeasure::Max => "E_max",
        }
    }
}

impl std::fmt::Display for ErrorMeasure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for ErrorMeasure {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for ErrorMeasure {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<ErrorMeasure, D::Error> {
        let name = String::deserialize(d)?;
        ErrorMeasure::parse(&name).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for m in ErrorMeasure::ALL {
            assert_eq!(ErrorMeasure::from_name(m.name()), Some(m));
            let json = serde_json::to_string(&m).unwrap();
            assert_eq!(serde_json::from_str::<ErrorMeasure>(&json).unwrap(), m);
        }
        let err = ErrorMeasure::parse("mean").unwrap_err();
        assert!(
            err.contains("\"mean\"") && err.contains("sum, rms, max"),
            "{err}"
        );
        assert_eq!(ErrorMeasure::default(), ErrorMeasure::Sum);
    }

    #[test]
    fn each_measure_reads_its_own_number() {
        let s = Score {
            e_sum: 7.0,
            e_max: 2.0,
            rms: 0.5,
            t: 9,
        };
        assert_eq!(ErrorMeasure::Sum.objectives(&s), [7.0, 9.0]);
        assert_eq!(ErrorMeasure::Rms.objectives(&s), [0.5, 9.0]);
        assert_eq!(ErrorMeasure::Max.objectives(&s), [2.0, 9.0]);
    }

    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn command_line_names_are_the_measure_names() {
        use clap::ValueEnum;
        for m in ErrorMeasure::ALL {
            assert_eq!(m.to_possible_value().unwrap().get_name(), m.name());
        }
    }
}
