//! The parameters `simplify` runs a method with: the catalogue's configuration of `--algo NAME`
//! with its `--evals` and `--error`, as the JSON the library's algorithm catalogue
//! ([`paretomesh::tiling::build_optimizer`]) takes and front.json records. The CLI's `run`
//! configures its method the same way ([`Algorithm::configure`], then [`Config::json`]), so both
//! give the same parameters by construction.
//!
//! [`Config::json`]: paretomesh::catalogue::Config::json

use crate::errors::value_error;
use paretomesh::catalogue::{Algorithm, Param, Params};
use paretomesh::measure::ErrorMeasure;
use pyo3::PyResult;

/// The full parameters of `method` stopping after about `evals` evaluations (the method's own
/// budget when `None`) and minimising the error measure named `error` (`sum` when `None`), as
/// `paretomesh run --algo METHOD [--evals N] [--error NAME]` sets them.
pub fn params(
    method: &str,
    evals: Option<u64>,
    error: Option<&str>,
) -> PyResult<serde_json::Value> {
    let error = error
        .map(ErrorMeasure::parse)
        .transpose()
        .map_err(value_error)?
        .unwrap_or_default();
    let algorithm = Algorithm::from_name(method).ok_or_else(|| {
        value_error(format!(
            "unknown method {method:?}; the methods are {}",
            Algorithm::ALL.map(|a| a.name()).join(", ")
        ))
    })?;
    if evals.is_some()
        && let Some(why) = algorithm.refusal(Param::MaxEvaluations)
    {
        return Err(value_error(format!(
            "evals does not apply to {method}: {why}"
        )));
    }
    let given = Params {
        max_evaluations: evals,
        error,
        ..Params::default()
    };
    let config = algorithm.configure(&given).map_err(value_error)?;
    Ok(config.json())
}
