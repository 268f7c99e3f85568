//! The parameters `simplify` runs a method with: the CLI's defaults for `--algo NAME` with its
//! `--evals`, as the JSON the library's algorithm catalogue
//! ([`paretomesh::tiling::build_optimizer`]) takes and front.json records.

use crate::errors::value_error;
use paretomesh::baselines::{DecimationParams, GreedyParams, GreedyStop};
use paretomesh::catalogue::Algorithm;
use paretomesh::evolution::{GaParams, MemeticParams, WeightedSumParams};
use pyo3::PyResult;

fn to_json<T: serde::Serialize>(params: &T) -> serde_json::Value {
    serde_json::to_value(params).expect("parameters are plain data")
}

/// The full parameters of `method` stopping after about `evals` evaluations (the method's own
/// budget when `None`), as `paretomesh run --algo METHOD [--evals N]` sets them.
pub fn params(method: &str, evals: Option<u64>) -> PyResult<serde_json::Value> {
    let ga = GaParams {
        max_evaluations: evals,
        ..GaParams::default()
    };
    Ok(match method {
        "memetic" => to_json(&MemeticParams {
            max_evaluations: evals,
            ..MemeticParams::default()
        }),
        "nsga2" => to_json(&ga),
        "weighted" => to_json(&WeightedSumParams {
            ga,
            ..WeightedSumParams::default()
        }),
        "greedy" => to_json(&GreedyParams {
            // One evaluation is one insertion after the four corners, as in the CLI.
            stop: match evals {
                Some(n) => GreedyStop::Points(
                    4usize.saturating_add(usize::try_from(n).unwrap_or(usize::MAX)),
                ),
                None => GreedyStop::AllPoints,
            },
            ..GreedyParams::default()
        }),
        "decimation" if evals.is_some() => {
            return Err(value_error(
                "edge decimation runs to its last reduction: evals does not apply",
            ));
        }
        "decimation" => to_json(&DecimationParams::default()),
        other => {
            return Err(value_error(format!(
                "unknown method {other:?}; the methods are {}",
                Algorithm::ALL.map(|a| a.name()).join(", ")
            )));
        }
    })
}
