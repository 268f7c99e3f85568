//! The protocol: which runs make an experiment, with which seeds and budgets, and how their
//! fronts are gathered into [`Results`].
//!
//! - NSGA-II is run [`Settings::runs`] times (paper: 10), run k with seed `seed + k`
//!   ([`run_seed`]).
//! - The weighted-sum GA: one *run* is one sweep over all 11 weights w = 0, 0.1, …, 1 — 11 GA
//!   runs inside one [`WeightedSum`](crate::evolution::WeightedSum) optimizer, whose 11 best
//!   solutions make that run's front. [`Settings::weighted_runs`] sweeps are run: as many as
//!   NSGA-II's runs at equal budgets, one (the paper's "once per weight") at per-weight budgets,
//!   where a sweep costs about 11 NSGA-II runs. With one sweep its HVR has no spread and the
//!   rank-sum test against it is not applicable (marked `n/a`).
//! - The GA budget ([`Budget`](super::Budget)): by default every GA run, whatever the method, stops after the
//!   same number of evaluations, so that the methods are compared at equal cost; the weighted-sum
//!   GA shares them between its weights. [`Budget::PerWeight`](super::Budget::PerWeight) is the paper's budget instead:
//!   population × generations for every GA run, so a weighted-sum sweep costs about 11 NSGA-II
//!   runs. Under it, NSGA-II's run k is exactly `paretomesh run GRID --algo nsga2 --seed
//!   <seed + k>` with the same population and generations.
//! - Deterministic methods (decimation at 5 %…50 %, greedy insertion) are run once: more runs
//!   would repeat the same front. They stop by their own rule, not by the GA budget.
//!
//! Every run is independent of every other, so [`plan`] lists them as [`Job`]s that any driver
//! may run in any order or in parallel ([`run_job`] is a pure function of its job), then
//! [`assemble`] puts the records back in plan order. [`run_all`] is the sequential driver; the
//! CLI runs the same jobs on every core.

use super::ExperimentError;
use super::method::Method;
use super::registry;
use super::results::{
    DatasetResults, GridSummary, MethodRuns, RESULTS_FORMAT, Results, RunRecord, Scales, Timings,
};
use super::settings::Settings;
use crate::evaluator::Evaluator;
use crate::heightfield::Heightfield;
use crate::metrics::Normalization;
use std::sync::Arc;

/// The seed of run `run` of a stochastic method: `base + run` (wrapping).
pub(crate) fn run_seed(base: u64, run: usize) -> u64 {
    base.wrapping_add(run as u64)
}

/// One input grid, ready to run on.
#[derive(Clone, Debug)]
pub struct Dataset {
    /// A short name for tables and file names.
    pub name: String,
    /// The grid.
    pub heightfield: Arc<Heightfield>,
    /// The unit of z, e.g. "m"; "height units" when unknown.
    pub e_units: String,
    /// The paper's normalisation of this grid.
    pub normalization: Normalization,
}

impl Dataset {
    /// A dataset with the paper's normalisation (E by the corner-only mesh's E, T by the full
    /// grid's triangle count).
    ///
    /// Errors: [`ExperimentError::Metrics`] when the corner-only mesh is already exact (a plane),
    /// so that E cannot be normalised by it.
    pub fn new(
        name: impl Into<String>,
        heightfield: Heightfield,
        e_units: impl Into<String>,
    ) -> Result<Dataset, ExperimentError> {
        let name = name.into();
        let heightfield = Arc::new(heightfield);
        let normalization = Normalization::from_evaluator(&mut Evaluator::new(heightfield.clone()))
            .map_err(|source| ExperimentError::Metrics {
                dataset: name.clone(),
                source,
            })?;
        Ok(Dataset {
            name,
            heightfield,
            e_units: e_units.into(),
            normalization,
        })
    }
}

/// One run to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Job {
    /// Index of the dataset.
    pub dataset: usize,
    /// The method.
    pub method: Method,
    /// Run number, from 0.
    pub run: usize,
    /// The seed (`None` for a deterministic method).
    pub seed: Option<u64>,
}

/// Every run of the experiment on `datasets` datasets, ordered by dataset, then method (in
/// settings order), then run number. [`assemble`] expects records in this order.
pub fn plan(datasets: usize, settings: &Settings) -> Vec<Job> {
    let mut jobs = Vec::new();
    for dataset in 0..datasets {
        for &method in &settings.methods {
            for run in 0..settings.runs_of(method) {
                let seed = method.is_stochastic().then(|| run_seed(settings.seed, run));
                jobs.push(Job {
                    dataset,
                    method,
                    run,
                    seed,
                });
            }
        }
    }
    jobs
}

/// Checks that every method of `settings` accepts its parameters on `dataset`, by building
/// each optimizer once without running it (cheap: constructors evaluate nothing). Call it before
/// the long part so that bad parameters fail at once.
pub fn check_methods(settings: &Settings, dataset: &Dataset) -> Result<(), ExperimentError> {
    settings.validate()?;
    for &method in &settings.methods {
        registry::params(method, settings)?;
        let seed = method.is_stochastic().then_some(settings.seed);
        registry::build(method, settings, dataset.heightfield.clone(), seed)?;
    }
    Ok(())
}

/// Runs one job to the end on `dataset` and records its front. A pure function of its inputs:
/// the same job gives the same record on any thread.
pub fn run_job(
    job: &Job,
    dataset: &Dataset,
    settings: &Settings,
) -> Result<RunRecord, ExperimentError> {
    let mut optimizer =
        registry::build(job.method, settings, dataset.heightfield.clone(), job.seed)?;
    let progress = optimizer.run_to_end();
    let front = optimizer.front().solutions().to_vec();
    if front.is_empty() {
        return Err(ExperimentError::EmptyFront {
            dataset: dataset.name.clone(),
            method: job.method,
            run: job.run,
        });
    }
    Ok(RunRecord {
        run: job.run,
        seed: job.seed,
        evaluations: progress.evaluations,
        front,
    })
}

/// Puts the records of `jobs` (as [`plan`] made them, records in the same order) into
/// [`Results`].
///
/// Errors: [`ExperimentError::Settings`] if `jobs` is not the plan of `datasets` and `settings`
/// or the record count differs.
pub fn assemble(
    settings: &Settings,
    datasets: &[Dataset],
    jobs: &[Job],
    records: Vec<RunRecord>,
    timings: Option<Timings>,
) -> Result<Results, ExperimentError> {
    if jobs != plan(datasets.len(), settings).as_slice() || records.len() != jobs.len() {
        return Err(ExperimentError::Settings(
            "the run records do not match the experiment's plan".to_string(),
        ));
    }
    let mut out: Vec<DatasetResults> = datasets
        .iter()
        .map(|d| {
            let hf = &d.heightfield;
            Ok(DatasetResults {
                external: Vec::new(),
                name: d.name.clone(),
                grid: GridSummary {
                    width: hf.width(),
                    height: hf.height(),
                    source: hf.source().to_string(),
                },
                e_units: d.e_units.clone(),
                normalization: Scales {
                    e_scale: d.normalization.e_scale(),
                    t_scale: d.normalization.t_scale(),
                },
                methods: settings
                    .methods
                    .iter()
                    .map(|&m| {
                        Ok(MethodRuns {
                            method: m,
                            params: registry::params(m, settings)?,
                            runs: Vec::new(),
                        })
                    })
                    .collect::<Result<_, ExperimentError>>()?,
            })
        })
        .collect::<Result<_, ExperimentError>>()?;
    for (job, record) in jobs.iter().zip(records) {
        let m = settings
            .methods
            .iter()
            .position(|&m| m == job.method)
            .expect("planned methods come from the settings");
        out[job.dataset].methods[m].runs.push(record);
    }
    Ok(Results {
        format: RESULTS_FORMAT.to_string(),
        settings: settings.clone(),
        datasets: out,
        timings,
        command: None,
    })
}

/// The sequential driver: checks the settings, runs every job in plan order, and assembles the
/// results (without timings).
pub fn run_all(datasets: &[Dataset], settings: &Settings) -> Result<Results, ExperimentError> {
    settings.validate()?;
    if let Some(first) = datasets.first() {
        check_methods(settings, first)?;
    }
    let jobs = plan(datasets.len(), settings);
    let records = jobs
        .iter()
        .map(|job| run_job(job, &datasets[job.dataset], settings))
        .collect::<Result<Vec<_>, _>>()?;
    assemble(settings, datasets, &jobs, records, None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::settings::{Budget, DEFAULT_EQUAL_EVALUATIONS};

    #[test]
    fn plan_runs_stochastic_methods_per_seed_and_deterministic_ones_once() {
        let settings = Settings {
            runs: 3,
            weighted_runs: 2,
            seed: 7,
            ..Settings::default()
        };
        let jobs = plan(2, &settings);
        // Per dataset: 3 NSGA-II + 2 weighted-sum sweeps + 1 decimation + 1 greedy + 3 memetic.
        assert_eq!(jobs.len(), 20);
        let seeds: Vec<_> = jobs[..10].iter().map(|j| (j.method, j.seed)).collect();
        assert_eq!(
            seeds,
            vec![
                (Method::NSGA2, Some(7)),
                (Method::NSGA2, Some(8)),
                (Method::NSGA2, Some(9)),
                (Method::WEIGHTED, Some(7)),
                (Method::WEIGHTED, Some(8)),
                (Method::DECIMATION, None),
                (Method::GREEDY, None),
                (Method::MEMETIC, Some(7)),
                (Method::MEMETIC, Some(8)),
                (Method::MEMETIC, Some(9)),
            ]
        );
        assert!(jobs[10..].iter().all(|j| j.dataset == 1));
        // Equal budgets: 10 runs of each GA, and the two deterministic methods once.
        assert_eq!(plan(1, &Settings::default()).len(), 32);
    }

    #[test]
    fn settings_without_a_budget_read_as_the_papers_per_weight_budget() {
        let mut json = serde_json::to_value(Settings::default()).unwrap();
        assert_eq!(
            json["budget"],
            serde_json::json!({"kind": "equal", "evaluations": DEFAULT_EQUAL_EVALUATIONS})
        );
        json.as_object_mut().unwrap().remove("budget");
        let read: Settings = serde_json::from_value(json).unwrap();
        assert_eq!(read.budget, Budget::PerWeight);
    }

    #[test]
    fn bad_settings_are_refused_with_a_reason() {
        let cases = [
            Settings {
                methods: vec![],
                ..Settings::default()
            },
            Settings {
                methods: vec![Method::GREEDY, Method::GREEDY],
                ..Settings::default()
            },
            Settings {
                runs: 0,
                ..Settings::default()
            },
            Settings {
                weighted_runs: 0,
                ..Settings::default()
            },
            Settings {
                reference_point: [f64::NAN, 1.1],
                ..Settings::default()
            },
            Settings {
                budget: Budget::Equal { evaluations: 10 },
                ..Settings::default()
            },
        ];
        for s in cases {
            assert!(matches!(s.validate(), Err(ExperimentError::Settings(_))));
        }
        assert_eq!(Settings::default().validate(), Ok(()));
    }
}
