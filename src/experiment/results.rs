//! results.json: every run's front with the settings, parameters and seeds that made it —
//! enough to recompute every table of the report (see [`Analysis`](super::Analysis)).
//!
//! Wall-clock times live only in [`Results::timings`], so two runs of the same experiment can
//! be compared byte for byte with that one field removed.

use super::method::Method;
use super::settings::Settings;
use crate::front::Solution;
use serde::{Deserialize, Serialize};

/// The identifier of this file format, written as `format`.
pub(crate) const RESULTS_FORMAT: &str = "paretomesh-experiment/1";

/// The whole experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Results {
    /// Always `RESULTS_FORMAT`.
    pub format: String,
    /// What was run.
    pub settings: Settings,
    /// One entry per input grid, in command-line order.
    pub datasets: Vec<DatasetResults>,
    /// Wall-clock times; `None` when not measured. Never part of a determinism comparison.
    pub timings: Option<Timings>,
    /// The command line that ran the experiment, `None` when not run from the command line.
    #[serde(default)]
    pub command: Option<String>,
}

/// The grid a dataset was run on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridSummary {
    /// W.
    pub width: usize,
    /// H.
    pub height: usize,
    /// How the grid was made (the height field's source note).
    pub source: String,
}

/// The per-dataset divisors of E and T (see [`Normalization`](crate::metrics::Normalization)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scales {
    /// E is divided by this: the E of the corner-only mesh.
    pub e_scale: f64,
    /// T is divided by this: the full grid's triangle count 2(W−1)(H−1).
    pub t_scale: f64,
}

/// Everything run on one input grid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DatasetResults {
    /// A short name (the file name without its extension), used in tables and file names.
    pub name: String,
    /// The grid.
    pub grid: GridSummary,
    /// The unit of z (and so of E), e.g. "m"; "height units" when the input does not say.
    pub e_units: String,
    /// The normalisation of the indicators.
    pub normalization: Scales,
    /// One entry per method, in the order of [`Settings::methods`].
    pub methods: Vec<MethodRuns>,
    /// Fronts made by other tools on this grid and re-scored here, in command-line order.
    #[serde(default)]
    pub external: Vec<ExternalFront>,
}

/// A front made by another tool on one grid, re-scored with the project's evaluator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExternalFront {
    /// The name the tables show.
    pub name: String,
    /// The file or directory it was read from, as given.
    pub source: String,
    /// Meshes read.
    pub meshes: usize,
    /// The meshes refused, each with its reason.
    pub rejected: Vec<RejectedMesh>,
    /// Valid meshes that are not a Delaunay triangulation of their points; every mesh is
    /// scored on its own triangles.
    pub not_delaunay: usize,
    /// The non-dominated valid meshes, re-scored, by increasing T.
    pub front: Vec<Solution>,
}

/// A mesh of an outside front that could not be used.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RejectedMesh {
    /// Which mesh (a file name or a position in the file).
    pub mesh: String,
    /// Why.
    pub reason: String,
}

impl ExternalFront {
    /// The meshes that passed every check (on the front or dominated).
    pub fn valid(&self) -> usize {
        self.meshes - self.rejected.len()
    }
}

/// Every run of one method on one dataset.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MethodRuns {
    /// The method.
    pub method: Method,
    /// Its parameters, as its params type serialises them.
    pub params: serde_json::Value,
    /// Its runs, by run number.
    pub runs: Vec<RunRecord>,
}

/// One run of one method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Run number, from 0.
    pub run: usize,
    /// The seed of its random generator (`None` for a deterministic method).
    pub seed: Option<u64>,
    /// Evaluations spent.
    pub evaluations: u64,
    /// Its final front, by increasing T.
    pub front: Vec<Solution>,
}

/// Wall-clock times of the experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// Wall time of the whole experiment (loading the grids, all runs, the analysis), in
    /// seconds.
    pub wall_seconds: f64,
    /// Worker threads used for the runs.
    pub threads: usize,
    /// Each run's own wall time.
    pub runs: Vec<RunTiming>,
}

/// The wall time of one run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunTiming {
    /// The dataset's name.
    pub dataset: String,
    /// The method.
    pub method: Method,
    /// The run number.
    pub run: usize,
    /// Milliseconds.
    pub millis: u64,
}

impl Results {
    /// The JSON text of results.json: compact (the kept sets of every run's front make it
    /// large; pretty-printing would put each index on its own line), keys in declaration order.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("results hold only numbers, strings and arrays")
    }

    /// Parses results.json; the error is serde's message.
    pub fn from_json(text: &str) -> Result<Results, String> {
        let results: Results = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if results.format != RESULTS_FORMAT {
            return Err(format!(
                "results.json has format {:?}, this version reads {RESULTS_FORMAT:?}",
                results.format
            ));
        }
        Ok(results)
    }
}
