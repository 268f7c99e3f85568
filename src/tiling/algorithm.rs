//! The one place the tiling builds an optimizer from an algorithm's name, its parameters as
//! JSON (as front.json records them) and a seed.

use super::TilingError;
use crate::baselines::{DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams};
use crate::evolution::{GaParams, Memetic, MemeticParams, Nsga2, WeightedSum, WeightedSumParams};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use serde::de::DeserializeOwned;
use std::sync::Arc;

/// The algorithm names [`build_optimizer`] knows (the CLI's `--algo` names).
pub const ALGORITHMS: [&str; 5] = ["memetic", "nsga2", "weighted", "greedy", "decimation"];

fn parse<T: DeserializeOwned>(
    algorithm: &str,
    params: &serde_json::Value,
) -> Result<T, TilingError> {
    serde_json::from_value(params.clone()).map_err(|e| TilingError::BadParams {
        algorithm: algorithm.to_string(),
        reason: e.to_string(),
    })
}

/// An optimizer `algorithm` on `hf` with `params` (its params type as JSON; `null` for the
/// defaults) and `seed` (ignored by the deterministic methods).
pub fn build_optimizer(
    hf: Arc<Heightfield>,
    algorithm: &str,
    params: &serde_json::Value,
    seed: u64,
) -> Result<Box<dyn Optimizer>, TilingError> {
    let bad = |e: String| TilingError::BadParams {
        algorithm: algorithm.to_string(),
        reason: e,
    };
    let params = if params.is_null() {
        &serde_json::Value::Object(Default::default())
    } else {
        params
    };
    Ok(match algorithm {
        "memetic" => {
            let p: MemeticParams =
                parse(algorithm, &with_defaults(MemeticParams::default(), params))?;
            Box::new(Memetic::new(hf, p, seed).map_err(|e| bad(e.to_string()))?)
        }
        "nsga2" => {
            let p: GaParams = parse(algorithm, &with_defaults(GaParams::default(), params))?;
            Box::new(Nsga2::new(hf, p, seed).map_err(|e| bad(e.to_string()))?)
        }
        "weighted" => {
            let p: WeightedSumParams = parse(
                algorithm,
                &with_defaults(WeightedSumParams::default(), params),
            )?;
            Box::new(WeightedSum::new(hf, p, seed).map_err(|e| bad(e.to_string()))?)
        }
        "greedy" => {
            let p: GreedyParams =
                parse(algorithm, &with_defaults(GreedyParams::default(), params))?;
            Box::new(GreedyInsertion::new(hf, p).map_err(|e| bad(e.to_string()))?)
        }
        "decimation" => {
            let p: DecimationParams = parse(
                algorithm,
                &with_defaults(DecimationParams::default(), params),
            )?;
            Box::new(EdgeDecimation::new(hf, p).map_err(|e| bad(e.to_string()))?)
        }
        other => return Err(TilingError::UnknownAlgorithm(other.to_string())),
    })
}

/// `defaults` as JSON with the fields of `given` laid over it, so a caller names only the
/// parameters it changes.
fn with_defaults<T: serde::Serialize>(defaults: T, given: &serde_json::Value) -> serde_json::Value {
    let mut out = serde_json::to_value(defaults).expect("parameters are plain data");
    if let (Some(out), Some(given)) = (out.as_object_mut(), given.as_object()) {
        for (k, v) in given {
            out.insert(k.clone(), v.clone());
        }
        return serde_json::Value::Object(out.clone());
    }
    given.clone()
}

/// The seed of tile `index` in a run with `seed`: a SplitMix64 mix of both, so neighbouring
/// tiles (and runs) get unrelated streams wherever the tile runs.
pub fn tile_seed(seed: u64, index: usize) -> u64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    mix(seed ^ mix(index as u64))
}
