//! The paper's experiment, reproducible: run every method on every dataset with the paper's
//! protocol, compare the fronts with the [`metrics`](crate::metrics), and write the report.
//!
//! - `method`: the methods by name and their fixed facts; `registry`: a method + settings +
//!   seed → a boxed [`Optimizer`](crate::optimizer::Optimizer), with its GA budget.
//! - `protocol`: the runs of an experiment ([`plan`], [`run_job`], [`assemble`],
//!   [`run_all`]) — seeds, run counts, the [`Budget`], and why the weighted-sum GA is counted
//!   the way it is.
//! - [`external`]: fronts made by other tools, read and re-scored with the project's evaluator;
//!   `contender`: a table column, a method or an outside front.
//! - `results`: results.json, every run's front and every outside front.
//! - `analysis`: every table's numbers, from results.json alone.
//! - `report`: report.md (the paper's Tables II–V); `svg`: the fronts figure.
//!
//! The library part is sequential and has no clock or file access (it builds for wasm32); the
//! CLI (`paretomesh experiment`) runs the planned jobs on every core and writes the files.
//! Results never depend on the thread count: each job is a pure function of its seed, and the
//! records are put back in plan order.

pub(crate) mod analysis;
pub(crate) mod contender;
pub mod external;
pub(crate) mod method;
pub(crate) mod protocol;
pub(crate) mod registry;
pub(crate) mod report;
pub(crate) mod results;
pub(crate) mod settings;
pub(crate) mod stats;
pub(crate) mod svg;

pub use analysis::{Analysis, DatasetAnalysis, Mark, MethodAnalysis, PairAnalysis, Pick};
pub use contender::Contender;
pub use external::{MeshInput, rescore};
pub use method::Method;
pub use protocol::{Dataset, Job, assemble, check_methods, plan, run_all, run_job};
pub use report::{format_significant, report_markdown};
pub(crate) use results::RESULTS_FORMAT;
pub use results::{
    DatasetResults, ExternalFront, GridSummary, MethodRuns, RejectedMesh, Results, RunRecord,
    RunTiming, Scales, Timings,
};
pub use settings::{Budget, DEFAULT_EQUAL_EVALUATIONS, Settings};
pub use stats::Summary;
pub use svg::fronts_svg;

use crate::metrics::MetricsError;
use std::fmt;

/// Why an experiment could not run or be analysed.
#[derive(Clone, Debug, PartialEq)]
pub enum ExperimentError {
    /// The settings are inconsistent; the message says how.
    Settings(String),
    /// A method refused its parameters; the message is the method's.
    Params {
        /// The method.
        method: Method,
        /// Its reason.
        message: String,
    },
    /// An indicator could not be computed on a dataset.
    Metrics {
        /// The dataset's name.
        dataset: String,
        /// The reason.
        source: MetricsError,
    },
    /// An outside front has no valid mesh, so nothing of it can be compared.
    EmptyExternal {
        /// The dataset's name.
        dataset: String,
        /// The outside front's name.
        name: String,
    },
    /// A run produced no solution (or a method has no run), so nothing can be compared.
    EmptyFront {
        /// The dataset's name.
        dataset: String,
        /// The method.
        method: Method,
        /// The run number.
        run: usize,
    },
}

impl fmt::Display for ExperimentError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Settings(m) => write!(f, "experiment settings: {m}"),
            Self::Params { method, message } => {
                write!(f, "{}: {message}", method.label())
            }
            Self::Metrics { dataset, source } => write!(f, "data set {dataset}: {source}"),
            Self::EmptyExternal { dataset, name } => write!(
                f,
                "data set {dataset}: the outside front {name} has no valid mesh"
            ),
            Self::EmptyFront {
                dataset,
                method,
                run,
            } => write!(
                f,
                "data set {dataset}: run {run} of {} produced no solution",
                method.label()
            ),
        }
    }
}

impl std::error::Error for ExperimentError {}
