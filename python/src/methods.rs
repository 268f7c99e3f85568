//! The methods `simplify` runs, by the names the CLI's `--algo` gives them, each built with the
//! defaults `paretomesh run` uses so that the same seed gives the CLI's front.

use crate::errors::value_error;
use paretomesh::baselines::{
    DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams, GreedyStop,
};
use paretomesh::evolution::{GaParams, Memetic, MemeticParams, Nsga2, WeightedSum, WeightedSumParams};
use paretomesh::heightfield::Heightfield;
use paretomesh::optimizer::Optimizer;
use pyo3::PyResult;
use std::sync::Arc;

/// The method names, in the order the CLI lists them.
pub const METHODS: [&str; 5] = ["memetic", "nsga2", "weighted", "greedy", "decimation"];

/// A ready optimizer and its parameters as front.json records them.
pub struct Built {
    pub optimizer: Box<dyn Optimizer + Send>,
    pub params: serde_json::Value,
}

fn to_json<T: serde::Serialize>(params: &T) -> serde_json::Value {
    serde_json::to_value(params).expect("parameters are plain data")
}

/// Builds `method` on `hf` with `seed`, stopping after about `evals` evaluations when given.
pub fn build(
    method: &str,
    hf: Arc<Heightfield>,
    seed: u64,
    evals: Option<u64>,
) -> PyResult<Built> {
    let ga = GaParams {
        max_evaluations: evals,
        ..GaParams::default()
    };
    Ok(match method {
        "memetic" => {
            let p = MemeticParams {
                max_evaluations: evals,
                ..MemeticParams::default()
            };
            let optimizer = Memetic::new(hf, p.clone(), seed).map_err(|e| value_error(e.to_string()))?;
            Built {
                params: to_json(&p),
                optimizer: Box::new(optimizer),
            }
        }
        "nsga2" => Built {
            params: to_json(&ga),
            optimizer: Box::new(Nsga2::new(hf, ga, seed).map_err(|e| value_error(e.to_string()))?),
        },
        "weighted" => {
            let p = WeightedSumParams {
                ga,
                ..WeightedSumParams::default()
            };
            Built {
                params: to_json(&p),
                optimizer: Box::new(
                    WeightedSum::new(hf, p, seed).map_err(|e| value_error(e.to_string()))?,
                ),
            }
        }
        "greedy" => {
            // One evaluation is one insertion after the four corners, as in the CLI.
            let stop = match evals {
                Some(n) => GreedyStop::Points(4usize.saturating_add(usize::try_from(n).unwrap_or(usize::MAX))),
                None => GreedyStop::AllPoints,
            };
            let p = GreedyParams {
                stop,
                ..GreedyParams::default()
            };
            Built {
                params: to_json(&p),
                optimizer: Box::new(GreedyInsertion::new(hf, p).map_err(|e| value_error(e.to_string()))?),
            }
        }
        "decimation" => {
            if evals.is_some() {
                return Err(value_error(
                    "edge decimation runs to its last reduction: evals does not apply",
                ));
            }
            let p = DecimationParams::default();
            Built {
                params: to_json(&p),
                optimizer: Box::new(EdgeDecimation::new(hf, p).map_err(|e| value_error(e.to_string()))?),
            }
        }
        other => {
            return Err(value_error(format!(
                "unknown method {other:?}; the methods are {}",
                METHODS.join(", ")
            )));
        }
    })
}
