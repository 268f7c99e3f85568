//! The method `simplify` runs: the catalogue's [`Config`] of `--algo NAME` with its `--evals`
//! and `--error`.
//! The CLI's `run` configures its method the same way ([`Algorithm::configure`]), so both give
//! the same parameters by construction. Dask ships the config to its tasks as JSON text
//! (its serde form, `{"algorithm": …, "params": …}`), read back with [`from_text`].

use crate::errors::value_error;
use paretomesh::catalogue::{Algorithm, Config, Param, Params};
use paretomesh::measure::ErrorMeasure;
use pyo3::PyResult;

/// The config of `method` stopping after about `evals` evaluations (the method's own budget
/// when `None`) and minimising the error measure named `error` (`sum` when `None`), as
/// `paretomesh run --algo METHOD [--evals N] [--error NAME]` sets it.
pub fn config(method: &str, evals: Option<u64>, error: Option<&str>) -> PyResult<Config> {
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
    algorithm.configure(&given).map_err(value_error)
}

/// A config shipped as JSON text (see [`config`]).
pub fn from_text(text: &str) -> PyResult<Config> {
    serde_json::from_str(text).map_err(|e| value_error(format!("config: {e}")))
}
