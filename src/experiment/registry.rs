//! The method registry: a method name, the experiment's settings and a seed → a ready
//! [`Optimizer`], and the parameters it runs with (written to results.json).
//!
//! Each method runs with its own crate defaults (the paper's settings) except the GA budget,
//! which comes from [`Settings::population`] and [`Settings::generations`].

use super::ExperimentError;
use super::method::Method;
use super::protocol::Settings;
use crate::baselines::{DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams};
use crate::evolution::{GaParams, Nsga2, WeightedSum, WeightedSumParams};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use std::sync::Arc;

fn ga_params(settings: &Settings) -> GaParams {
    GaParams {
        population: settings.population,
        generations: settings.generations,
        ..GaParams::default()
    }
}

fn weighted_params(settings: &Settings) -> WeightedSumParams {
    WeightedSumParams {
        ga: ga_params(settings),
        ..WeightedSumParams::default()
    }
}

/// The parameters `method` runs with under `settings`, as its params type serialises them.
pub fn params(method: Method, settings: &Settings) -> Result<serde_json::Value, ExperimentError> {
    let value = match method {
        Method::Nsga2 => serde_json::to_value(ga_params(settings)),
        Method::Weighted => serde_json::to_value(weighted_params(settings)),
        Method::Decimation => serde_json::to_value(DecimationParams::default()),
        Method::Greedy => serde_json::to_value(GreedyParams::default()),
    };
    value.map_err(|e| ExperimentError::Params {
        method,
        message: e.to_string(),
    })
}

/// A fresh optimizer for `method` on `hf`. `seed` is used by stochastic methods (and must be
/// `Some` for them); deterministic methods ignore it.
///
/// Errors: [`ExperimentError::Params`] when the method refuses its parameters (e.g. a
/// population under 2), or a stochastic method gets no seed.
pub fn build(
    method: Method,
    settings: &Settings,
    hf: Arc<Heightfield>,
    seed: Option<u64>,
) -> Result<Box<dyn Optimizer + Send>, ExperimentError> {
    let refused = |message: String| ExperimentError::Params { method, message };
    let need_seed = || seed.ok_or_else(|| refused("a stochastic method needs a seed".into()));
    Ok(match method {
        Method::Nsga2 => Box::new(
            Nsga2::new(hf, ga_params(settings), need_seed()?)
                .map_err(|e| refused(e.to_string()))?,
        ),
        Method::Weighted => Box::new(
            WeightedSum::new(hf, weighted_params(settings), need_seed()?)
                .map_err(|e| refused(e.to_string()))?,
        ),
        Method::Decimation => Box::new(
            EdgeDecimation::new(hf, DecimationParams::default())
                .map_err(|e| refused(e.to_string()))?,
        ),
        Method::Greedy => Box::new(
            GreedyInsertion::new(hf, GreedyParams::default())
                .map_err(|e| refused(e.to_string()))?,
        ),
    })
}
