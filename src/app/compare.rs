//! Compare mode: the methods of `paretomesh experiment` (every method of the catalogue) run
//! on one surface with one set of GA parameters and one seed, advanced together inside the frame budget, and compared with the
//! experiment's own analysis. Pure Rust with no DOM, so it is tested directly.
//!
//! Each method runs in its own [`App`] (the single-run app state), so it is stepped exactly as
//! a single run is: [`CompareRun::tick`] shares one frame budget between the unfinished methods,
//! and each gets a time-budgeted [`App::tick`] slice. Since slicing never changes an
//! optimizer's result, each method reaches exactly the front it reaches when run alone with the
//! same parameters and seed.
//!
//! The indicator table ([`CompareTable`]) is [`Analysis::of`] — the code that computes the
//! tables of `paretomesh experiment` — on a one-dataset, one-run-per-method [`Results`]: one
//! common normalisation for the fronts (E by the corner-only mesh's E, T by the full grid's
//! triangle count), the default reference point (1.1, 1.1), the reference front = the
//! non-dominated merge of the fronts, and the trade-off picks' weights drawn from the run's
//! seed.

use super::algorithms::{self, Algorithm, Field, Params};
use super::state::{App, RunConfig, Surface};
use crate::evaluator::Evaluator;
use crate::experiment::{
    Analysis, Budget, DatasetResults, GridSummary, Method, MethodRuns, Pick, RESULTS_FORMAT,
    Results, RunRecord, Scales, Settings,
};
use crate::front::{Front, Solution};
use crate::measure::ErrorMeasure;
use crate::metrics::{DEFAULT_REFERENCE_POINT, Normalization, Point};
use crate::pick::{self, pick_in_front};
use serde::Serialize;

/// The compared methods: every method of the catalogue, in the order of the experiment's
/// tables (compare mode runs each full method; ablation variants are the experiment's).
pub const METHODS: [Method; Algorithm::ALL.len()] = {
    let mut methods = [Method::MEMETIC; Algorithm::ALL.len()];
    let mut k = 0;
    while k < methods.len() {
        methods[k] = Method::of(Algorithm::ALL[k]);
        k += 1;
    }
    methods
};

/// Least time between two recomputations of the live table while the run goes on, in ms.
pub const TABLE_INTERVAL_MS: f64 = 250.0;

/// True when a comparison reads `field` of the form: one of the compared methods uses it.
pub fn reads(field: Field) -> bool {
    METHODS
        .iter()
        .any(|&m| algorithms::uses(m.algorithm, field))
}

/// What one [`CompareRun::tick`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CompareTick {
    /// `Optimizer::step` calls made, over all methods.
    pub steps: u32,
    /// Evaluations spent, over all methods.
    pub evaluations: u64,
    /// Which methods got a slice, in [`METHODS`] order.
    pub served: [bool; METHODS.len()],
    /// The last unfinished method finished in this tick.
    pub finished: bool,
}

/// The three picks of one method's front (the experiment's Table IV), with their positions in
/// the front as of the table's computation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Picks {
    /// The member with the lowest E.
    pub best_error: Pick,
    /// The member with the fewest triangles.
    pub fewest_triangles: Pick,
    /// The paper's trade-off pick (eq. 7–9).
    pub trade_off: Pick,
}

/// One method's row of the table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MethodRow {
    /// The method.
    pub method: Method,
    /// Members of its front when the table was computed.
    pub front_size: usize,
    /// True once the method finished.
    pub done: bool,
    /// Evaluations it has spent.
    pub evaluations: u64,
    /// HV(front) / HV(reference front), normalised (Table II); `None` while its front is empty.
    pub hvr: Option<f64>,
    /// Its picks (Table IV); `None` while its front is empty.
    pub picks: Option<Picks>,
}

/// The binary indicators of one ordered pair of methods (Table III).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairRow {
    /// A.
    pub a: Method,
    /// B.
    pub b: Method,
    /// The additive epsilon I_ε+(A, B) in normalised units; `None` while a front is empty.
    pub epsilon: Option<f64>,
    /// Zitzler's coverage C(A, B) (weak dominance); `None` while a front is empty.
    pub coverage: Option<f64>,
}

/// The live table of compare mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareTable {
    /// The common normalisation of the fronts.
    pub normalization: Normalization,
    /// The hypervolume reference point, normalised.
    pub reference_point: Point,
    /// The seed of the trade-off picks' weights.
    pub seed: u64,
    /// Points of the reference front (the merge of the non-empty fronts).
    pub reference_front_size: usize,
    /// One row per method, in [`METHODS`] order.
    pub methods: Vec<MethodRow>,
    /// Every ordered pair (A, B) with A ≠ B, A-major in [`METHODS`] order (12 rows).
    pub pairs: Vec<PairRow>,
    /// True when every method had finished: the table is final.
    pub complete: bool,
}

/// One method of a compare run.
struct Lane {
    method: Method,
    app: App,
}

/// A compare run: every method on one surface with one set of parameters.
pub struct CompareRun {
    surface: Surface,
    params: Params,
    lanes: Vec<Lane>,
    /// The lane served first in the next tick (rotates, so no method always waits).
    cursor: usize,
    running: bool,
    normalization: Result<Normalization, String>,
    table: Option<Result<CompareTable, String>>,
    table_revision: Option<u64>,
    table_at_ms: f64,
}

impl CompareRun {
    /// Every method on `surface` with `params` (the GA parameters and seed; the classical
    /// methods use their defaults, as in the experiment), paused, nothing done yet.
    ///
    /// Every method is compared in (E_sum, T), the measure they all take, whatever `params`'
    /// error measure. Errors: the message of the first method that refuses the parameters.
    pub fn new(surface: Surface, params: Params) -> Result<CompareRun, String> {
        let params = Params {
            error: ErrorMeasure::Sum,
            ..params
        };
        let mut lanes = Vec::with_capacity(METHODS.len());
        for method in METHODS {
            let config = RunConfig {
                algorithm: method.algorithm,
                params: params.clone(),
                ..RunConfig::default()
            };
            let mut app = App::new(surface.clone(), config);
            // Builds the optimizer now, so bad parameters are reported before anything runs.
            app.run().map_err(|e| format!("{}: {e}", method.label()))?;
            app.pause();
            lanes.push(Lane { method, app });
        }
        let normalization =
            Normalization::from_evaluator(&mut Evaluator::new(surface.heightfield.clone()))
                .map_err(|e| e.to_string());
        Ok(CompareRun {
            surface,
            params,
            lanes,
            cursor: 0,
            running: false,
            normalization,
            table: None,
            table_revision: None,
            table_at_ms: f64::NEG_INFINITY,
        })
    }

    /// The surface the run is on.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }

    /// The parameters the run was started with.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Starts or resumes the methods that have not finished.
    pub fn run(&mut self) {
        for lane in &mut self.lanes {
            if !lane.app.status().done {
                // The optimizer was built in `new`, so this cannot fail.
                let _ = lane.app.run();
            }
        }
        self.running = !self.is_done();
    }

    /// Pauses every method; [`CompareRun::run`] resumes.
    pub fn pause(&mut self) {
        for lane in &mut self.lanes {
            lane.app.pause();
        }
        self.running = false;
    }

    /// True while running.
    pub fn is_running(&self) -> bool {
        self.running
    }

    /// True once every method has finished.
    pub fn is_done(&self) -> bool {
        self.lanes.iter().all(|l| l.app.status().done)
    }

    /// Advances the unfinished methods for one frame of `budget_ms` (in `clock()`'s ms).
    ///
    /// The methods are served one after another, starting with a different one each frame;
    /// each gets an [`App::tick`] slice of the time left divided by the unfinished methods not
    /// yet served, so a method that finishes early leaves its time to the others. Once the
    /// budget is spent no further slice starts (the methods left out are served first in the
    /// next frame). So the frame stays within the budget plus what [`App::tick`] allows each
    /// slice (about a tenth of its slice and one unit). Does nothing when paused.
    pub fn tick(&mut self, budget_ms: f64, clock: &mut dyn FnMut() -> f64) -> CompareTick {
        let mut report = CompareTick::default();
        if !self.running {
            return report;
        }
        let n = self.lanes.len();
        let start = clock();
        let mut now = start;
        let mut next_cursor = (self.cursor + 1) % n;
        for k in 0..n {
            let i = (self.cursor + k) % n;
            if !self.lanes[i].app.is_running() {
                continue;
            }
            let left = budget_ms - (now - start);
            if left <= 0.0 {
                next_cursor = i;
                break;
            }
            let waiting = (k..n)
                .filter(|&j| self.lanes[(self.cursor + j) % n].app.is_running())
                .count();
            let slice = self.lanes[i].app.tick(left / waiting as f64, clock);
            report.steps += slice.steps;
            report.evaluations += slice.evaluations;
            report.served[i] = true;
            now = clock();
        }
        self.cursor = next_cursor;
        if self.is_done() {
            self.running = false;
            report.finished = true;
        }
        report
    }

    /// The paper's trade-off pick ([`pick::Pick::TradeOff`]) of the fronts merged, with the
    /// weights drawn from the run's seed: the best balance any method found. `None` while every
    /// front is empty.
    pub fn trade_off_solution(&self) -> Option<Solution> {
        let merged = Front::merged(
            self.lanes
                .iter()
                .filter_map(|l| l.app.front())
                .flat_map(|f| f.solutions()),
        );
        pick_in_front(&merged, pick::Pick::TradeOff, self.params.seed, 0)
            .ok()
            .cloned()
    }

    /// The methods, in [`METHODS`] order.
    #[cfg(test)]
    pub fn methods(&self) -> impl Iterator<Item = Method> + '_ {
        self.lanes.iter().map(|l| l.method)
    }

    /// The current front of method `k` (in [`METHODS`] order).
    pub fn front(&self, k: usize) -> Option<&Front> {
        self.lanes.get(k).and_then(|l| l.app.front())
    }

    /// The status of method `k` (in [`METHODS`] order).
    #[cfg(test)]
    pub fn status(&self, k: usize) -> Option<super::state::Status> {
        self.lanes.get(k).map(|l| l.app.status())
    }

    /// Evaluations and optimisation time (ms) summed over the methods.
    pub fn totals(&self) -> (u64, f64) {
        self.lanes.iter().fold((0, 0.0), |(e, ms), l| {
            let s = l.app.status();
            (e + s.evaluations, ms + s.elapsed_ms)
        })
    }

    /// A counter that changes whenever a front may have changed.
    pub fn revision(&self) -> u64 {
        self.lanes.iter().map(|l| l.app.revision()).sum()
    }

    /// The fronts as the experiment's [`Results`]: one dataset, one run per method with a
    /// non-empty front (the kept sets left out: the indicators need only E and T).
    pub fn results(&self) -> Result<Results, String> {
        let n = self.normalization.clone()?;
        let hf = &self.surface.heightfield;
        let methods: Vec<MethodRuns> = self
            .lanes
            .iter()
            .filter_map(|l| self.method_runs(l))
            .collect();
        Ok(Results {
            format: RESULTS_FORMAT.to_string(),
            settings: Settings {
                methods: methods.iter().map(|m| m.method).collect(),
                runs: 1,
                weighted_runs: 1,
                seed: self.params.seed,
                population: self.params.population,
                generations: self.params.generations,
                budget: Budget::PerWeight,
                reference_point: DEFAULT_REFERENCE_POINT,
            },
            datasets: vec![DatasetResults {
                name: self.surface.name.clone(),
                grid: GridSummary {
                    width: hf.width(),
                    height: hf.height(),
                    source: hf.source().to_string(),
                },
                e_units: String::new(),
                normalization: Scales {
                    e_scale: n.e_scale(),
                    t_scale: n.t_scale(),
                },
                methods,
                external: Vec::new(),
            }],
            timings: None,
            command: None,
        })
    }

    /// A lane's front as one run of its method, `None` while the front is empty.
    fn method_runs(&self, lane: &Lane) -> Option<MethodRuns> {
        let front = lane.app.front().filter(|f| !f.is_empty())?;
        let front = front
            .solutions()
            .iter()
            .map(|s| Solution {
                kept: Vec::new(),
                ..s.clone()
            })
            .collect();
        Some(MethodRuns {
            method: lane.method,
            params: super::algorithms::params_json(lane.app.config().algorithm, &self.params),
            runs: vec![RunRecord {
                run: 0,
                seed: lane.method.is_stochastic().then_some(self.params.seed),
                evaluations: lane.app.status().evaluations,
                front,
            }],
        })
    }

    /// Computes the table from the current fronts with the experiment's [`Analysis::of`].
    /// Methods whose front is still empty have empty cells, and so do their pairs.
    ///
    /// Errors: the surface has no normalisation (a plane), or an indicator is undefined.
    pub fn compute_table(&self) -> Result<CompareTable, String> {
        let results = self.results()?;
        let normalization = self.normalization.clone()?;
        let present = &results.settings.methods;
        let dataset = if present.is_empty() {
            None
        } else {
            let analysis = Analysis::of(&results).map_err(|e| e.to_string())?;
            analysis.datasets.into_iter().next()
        };
        let of = |m: Method| {
            dataset
                .as_ref()
                .and_then(|d| d.methods.iter().find(|a| a.method == m))
        };
        let methods = self
            .lanes
            .iter()
            .map(|l| {
                let analysed = of(l.method);
                MethodRow {
                    method: l.method,
                    front_size: l.app.front().map_or(0, |f| f.len()),
                    done: l.app.status().done,
                    evaluations: l.app.status().evaluations,
                    hvr: analysed.map(|a| a.hvr.mean),
                    picks: analysed.map(|a| Picks {
                        best_error: a.best_error,
                        fewest_triangles: a.fewest_triangles,
                        trade_off: a.trade_off,
                    }),
                }
            })
            .collect();
        let mut pairs = Vec::new();
        for a in METHODS {
            for b in METHODS {
                if a == b {
                    continue;
                }
                let analysed = dataset
                    .as_ref()
                    .and_then(|d| d.pairs.iter().find(|p| p.a == a && p.b == b));
                pairs.push(PairRow {
                    a,
                    b,
                    epsilon: analysed.map(|p| p.epsilon.mean),
                    coverage: analysed.map(|p| p.coverage.mean),
                });
            }
        }
        Ok(CompareTable {
            normalization,
            reference_point: results.settings.reference_point,
            seed: self.params.seed,
            reference_front_size: dataset.as_ref().map_or(0, |d| d.reference_front.len()),
            methods,
            pairs,
            complete: self.is_done(),
        })
    }

    /// Recomputes the table when a front changed since the last computation and either
    /// [`TABLE_INTERVAL_MS`] have passed since it (at `now_ms`) or the run is no longer running
    /// (so the last table of a finished or paused run is exact). Returns true when it
    /// recomputed.
    pub fn refresh_table(&mut self, now_ms: f64) -> bool {
        let revision = self.revision();
        if self.table_revision == Some(revision) {
            return false;
        }
        if self.running && now_ms - self.table_at_ms < TABLE_INTERVAL_MS {
            return false;
        }
        self.table = Some(self.compute_table());
        self.table_revision = Some(revision);
        self.table_at_ms = now_ms;
        true
    }

    /// The last computed table (or why it could not be computed); `None` before the first.
    pub fn table(&self) -> Option<&Result<CompareTable, String>> {
        self.table.as_ref()
    }
}
