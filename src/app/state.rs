//! The app state: the surface, the chosen algorithm and its parameters, the running optimizer,
//! run/pause, and the selected solution. Pure Rust with no DOM, so it is tested directly.
//!
//! The optimizer advances in time-budgeted slices: [`App::tick`] calls
//! [`Optimizer::step`](crate::optimizer::Optimizer::step) with small evaluation budgets until
//! the frame's time budget is spent. Since slicing never changes
//! an optimizer's result (see [`crate::optimizer`]), the browser reaches exactly the front the
//! CLI reaches with the same seed.

use super::algorithms::{self, Algorithm, Params, Running};
use super::pool::{PoolRun, PoolSetup};
use super::tiled_run::TiledRun;
use crate::evaluator::Evaluator;
use crate::evaluator::exact::predicates::Lattice;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use crate::optimizer::{Optimizer, Progress};
use crate::pick::{Pick, pick_in_front};
use crate::tiling::{TileFront, TilePart, TilePlan};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The most triangles the 3-D view draws at once; a selected member over it is drawn as the
/// member of least error within it (see [`App::selected_mesh`]).
pub(crate) const MAX_DRAWN_TRIANGLES: usize = 2_000_000;

/// The member the 3-D view draws for a tiled run's selection, the run's plan and the member's
/// tile parts.
pub(crate) type DrawnParts = (Solution, TilePlan, Vec<TilePart>);

/// Default time budget of one frame's optimisation slice, in milliseconds.
pub(crate) const DEFAULT_BUDGET_MS: f64 = 8.0;

/// How much of the longest recent step call a tick still expects of its next call, per frame
/// since it was seen (see [`App::tick`]).
pub(crate) const SLOW_CALL_FADE: f64 = 0.5;

/// What the user chose: serialisable, so a share link can carry it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct RunConfig {
    /// Which algorithm runs.
    pub algorithm: Algorithm,
    /// Its parameters.
    pub params: Params,
    /// Milliseconds of optimisation per animation frame.
    pub budget_ms: f64,
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            algorithm: Algorithm::DEFAULT,
            params: Params::default(),
            budget_ms: DEFAULT_BUDGET_MS,
        }
    }
}

/// The loaded surface and what is known about it.
#[derive(Clone, Debug)]
pub(crate) struct Surface {
    /// Name shown to the user (file name or built-in name).
    pub name: String,
    /// The height field.
    pub heightfield: Arc<Heightfield>,
}

/// The numbers of the status line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Status {
    /// Generations (or sweeps) completed.
    pub generation: u64,
    /// Evaluations done.
    pub evaluations: u64,
    /// Evaluations per second of optimisation time.
    pub evaluations_per_second: f64,
    /// Members of the archive front.
    pub front_size: usize,
    /// Milliseconds spent optimising (pauses excluded).
    pub elapsed_ms: f64,
    /// True once the algorithm finished.
    pub done: bool,
}

/// What one [`App::tick`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct TickReport {
    /// [`Optimizer::step`](crate::optimizer::Optimizer::step) calls made.
    pub steps: u32,
    /// Evaluations spent in this tick.
    pub evaluations: u64,
}

/// The app: one surface, one run.
pub(crate) struct App {
    surface: Surface,
    config: RunConfig,
    optimizer: Option<Box<dyn Running>>,
    running: bool,
    elapsed_ms: f64,
    /// Evaluations per step call, adapted so a call takes about a tenth of the budget.
    chunk: u64,
    /// The longest step call of recent frames, in ms, fading by [`SLOW_CALL_FADE`] per frame.
    slowest_call_ms: f64,
    selected: Option<Solution>,
    revision: u64,
    /// While re-running a shared run: the generation to stop at, and the front index to select
    /// there.
    reproduction: Option<Reproduction>,
    /// Whether and how runs go to a pool of Web Workers.
    pool: PoolSetup,
    /// The id the next pool run gets (ids tell a run's worker reports from a former run's).
    next_pool_run: u64,
    /// The clock at the last tick of a running pool run: its time is wall time, not the
    /// frames' slices.
    pool_clock: Option<f64>,
}

/// Where a re-run of a shared run stops and what it selects there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Reproduction {
    /// Generations (or sweeps) to complete.
    pub generations: u64,
    /// Front index (by increasing T) to select when they are (`None`: the selection stays).
    pub selected: Option<usize>,
}

impl App {
    /// An app on `surface` with `config`, not running, nothing selected.
    pub(crate) fn new(surface: Surface, config: RunConfig) -> Self {
        Self {
            surface,
            config,
            optimizer: None,
            running: false,
            elapsed_ms: 0.0,
            chunk: 1,
            slowest_call_ms: 0.0,
            selected: None,
            revision: 0,
            reproduction: None,
            pool: PoolSetup::default(),
            next_pool_run: 1,
            pool_clock: None,
        }
    }

    /// Sets whether and how runs go to a pool of Web Workers; the current run is discarded
    /// when that changes.
    pub(crate) fn set_pool_setup(&mut self, setup: PoolSetup) {
        if setup != self.pool {
            self.pool = setup;
            self.reset();
        }
    }

    /// How runs go to a pool of Web Workers.
    pub(crate) fn pool_setup(&self) -> PoolSetup {
        self.pool
    }

    /// The current run when its work happens in a pool of Web Workers.
    pub(crate) fn pool_run(&mut self) -> Option<&mut PoolRun> {
        self.optimizer
            .as_mut()?
            .as_any_mut()?
            .downcast_mut::<PoolRun>()
    }

    /// The tiles a run of the current surface is cut into; `None` when it fits in one tile.
    fn tile_plan(&self) -> Result<Option<TilePlan>, String> {
        let hf = &self.surface.heightfield;
        let plan =
            TilePlan::new(hf.width(), hf.height(), self.pool.tile).map_err(|e| e.to_string())?;
        Ok((!plan.is_single()).then_some(plan))
    }

    /// Applies a worker's tile front to the pool run (see [`PoolRun::report_tile`]).
    pub(crate) fn pool_report_tile(
        &mut self,
        run: u64,
        index: usize,
        front: TileFront,
    ) -> Result<(), String> {
        let Some(pool) = self.pool_run() else {
            return Ok(());
        };
        let changed = pool.report_tile(run, index, front)?;
        let done = pool.progress().done;
        self.revision += 1;
        if done {
            self.running = false;
            self.select_at_run_end();
        } else if changed {
            // The selection names a member of the former whole-grid front: keep the member of
            // least error within its triangles.
            self.reselect_within();
        }
        Ok(())
    }

    /// After the front changed under a selection that left it, selects the member of least
    /// error within the selection's triangles (or none).
    fn reselect_within(&mut self) {
        let Some(t) = self.selected.as_ref().map(|s| s.t) else {
            return;
        };
        if self.selected_front_index().is_none() {
            self.selected = self.front().and_then(|f| f.within(t).cloned());
        }
    }

    /// The tiles of the current run, when it is a tiled pool run.
    pub(crate) fn tiled_run(&self) -> Option<&TiledRun> {
        self.optimizer
            .as_ref()?
            .as_any()?
            .downcast_ref::<PoolRun>()?
            .tiled()
    }

    /// The mesh of the selected member; `None` when nothing is selected. A member of a tiled
    /// run is rebuilt from its tiles' fronts (the union of its tiles' canonical
    /// triangulations); others are triangulated from their kept set. With `max_triangles`, a
    /// member over it is stood in for by the member of least error within it (the mesh the 3-D
    /// view draws: a GPU draws a few million triangles smoothly, not tens of millions).
    pub(crate) fn selected_mesh(
        &self,
        max_triangles: Option<usize>,
    ) -> Option<Result<ShownMesh, String>> {
        let member = self.drawn_member(max_triangles)?;
        let hf = self.surface.heightfield.clone();
        if let Some(tiled) = self.tiled_run() {
            return Some(
                tiled
                    .mesh(&hf, member.e_sum, member.t)
                    .map(|m| shown_triangles(&hf, m.kept, m.triangles, member.e_sum)),
            );
        }
        Some(shown_mesh(&hf, &member.kept))
    }

    /// The member to draw for the selection when it belongs to a tiled run, with its tile
    /// parts, for a worker to build its mesh ([`crate::tiling::mesh_of_parts`]); `None` when
    /// nothing is selected or the run is not tiled. `max_triangles` as in
    /// [`App::selected_mesh`].
    pub(crate) fn selected_tiled_parts(
        &self,
        max_triangles: Option<usize>,
    ) -> Option<Result<DrawnParts, String>> {
        let member = self.drawn_member(max_triangles)?;
        let tiled = self.tiled_run()?;
        Some(
            tiled
                .parts(member.e_sum, member.t)
                .map(|parts| (member, tiled.plan().clone(), parts)),
        )
    }

    /// The selection, or with `max_triangles` the member of least error within it that stands
    /// in for a larger selection.
    fn drawn_member(&self, max_triangles: Option<usize>) -> Option<Solution> {
        let member = self.selected.clone()?;
        if let Some(max) = max_triangles
            && member.t > max
            && let Some(coarser) = self.front().and_then(|f| f.within(max))
        {
            return Some(coarser.clone());
        }
        Some(member)
    }

    /// Applies a worker's report to the pool run (see [`PoolRun::report`]); when its last job
    /// ends the run stops and the trade-off pick is selected, as after a run on the page.
    pub(crate) fn pool_report(
        &mut self,
        run: u64,
        index: usize,
        front: Front,
        progress: Progress,
    ) -> Result<(), String> {
        let Some(pool) = self.pool_run() else {
            return Ok(());
        };
        if pool.report(run, index, front, progress)? {
            let done = pool.progress().done;
            self.revision += 1;
            if done {
                self.running = false;
                self.select_at_run_end();
            }
        }
        Ok(())
    }

    /// A worker of pool run `run` failed on job `index` (`None`: a job could not be handed
    /// out): the run stops with `message`.
    pub(crate) fn pool_failed(&mut self, run: u64, index: Option<usize>, message: &str) {
        if let Some(pool) = self.pool_run() {
            pool.fail(run, index, message);
            if pool.failure().is_some() {
                self.running = false;
                self.revision += 1;
            }
        }
    }

    /// The surface.
    pub(crate) fn surface(&self) -> &Surface {
        &self.surface
    }

    /// The configuration.
    pub(crate) fn config(&self) -> &RunConfig {
        &self.config
    }

    /// Replaces the configuration; the current run is discarded (its results belong to the old
    /// parameters).
    pub(crate) fn set_config(&mut self, config: RunConfig) {
        if config.algorithm != self.config.algorithm || config.params != self.config.params {
            self.reset();
        }
        self.config = config;
    }

    /// Replaces the surface and discards the run and the selection.
    pub(crate) fn set_surface(&mut self, surface: Surface) {
        self.surface = surface;
        self.reset();
    }

    /// Discards the run and the selection; the next run starts from scratch.
    pub(crate) fn reset(&mut self) {
        self.optimizer = None;
        self.running = false;
        self.elapsed_ms = 0.0;
        self.chunk = 1;
        self.slowest_call_ms = 0.0;
        self.selected = None;
        self.reproduction = None;
        self.pool_clock = None;
        self.revision += 1;
    }

    /// Re-runs the current configuration from scratch to the end of generation
    /// `target.generations`, then pauses and selects `target.selected` (ignored when the front
    /// is shorter). With 0 generations nothing runs. Pausing and resuming keep the target;
    /// [`App::step_once`] and [`App::reset`] drop it.
    pub(crate) fn reproduce(&mut self, target: Reproduction) -> Result<(), String> {
        self.reset();
        if target.generations == 0 {
            return Ok(());
        }
        self.ensure_optimizer(false)?;
        self.reproduction = Some(target);
        self.running = true;
        Ok(())
    }

    /// Runs on (from where the run stands) to the end of generation `generations`, then
    /// pauses; the selection stays. Does nothing when that generation is already complete.
    pub(crate) fn advance_to(&mut self, generations: u64) -> Result<(), String> {
        let optimizer = self.ensure_optimizer(false)?;
        let p = optimizer.progress();
        if p.done || p.generation >= generations {
            return Ok(());
        }
        self.reproduction = Some(Reproduction {
            generations,
            selected: None,
        });
        self.running = true;
        Ok(())
    }

    /// Shows `solution` (from anywhere: a crossover child, say) as the selection.
    pub(crate) fn show_solution(&mut self, solution: Solution) {
        self.selected = Some(solution);
        self.revision += 1;
    }

    /// The re-run in progress, if any.
    pub(crate) fn reproduction(&self) -> Option<Reproduction> {
        self.reproduction
    }

    /// Builds the optimizer when there is none yet: a pool run when `pooled` and the pool
    /// setup wants one for this surface (a surface cut into several jobs always does), else
    /// the algorithm on the page. Re-running a shared run to a generation and single steps stay
    /// on the page: they stop between generations, which the workers do not. Fails with a
    /// message for the user when the parameters are invalid for this surface.
    fn ensure_optimizer(&mut self, pooled: bool) -> Result<&mut Box<dyn Running>, String> {
        if self.optimizer.is_none() {
            let plan = self.tile_plan()?;
            if plan.is_some() && !pooled {
                return Err("a grid cut into tiles runs in Web Workers, whole: use Run".to_string());
            }
            self.optimizer = Some(if pooled && (self.pool.always || plan.is_some()) {
                let id = self.next_pool_run;
                self.next_pool_run += 1;
                Box::new(PoolRun::new(
                    id,
                    self.config.algorithm,
                    self.config.params.clone(),
                    plan,
                )?)
            } else {
                algorithms::build(
                    self.config.algorithm,
                    &self.config.params,
                    self.surface.heightfield.clone(),
                )?
            });
        }
        Ok(self.optimizer.as_mut().expect("just built"))
    }

    /// Starts or resumes running.
    pub(crate) fn run(&mut self) -> Result<(), String> {
        if self
            .optimizer
            .as_mut()
            .and_then(|o| o.as_any_mut()?.downcast_mut::<PoolRun>())
            .is_some_and(|p| p.failure().is_some())
        {
            // A failed pool run starts again from scratch.
            self.reset();
        }
        self.ensure_optimizer(true)?;
        self.running = true;
        Ok(())
    }

    /// Pauses; [`App::run`] resumes.
    pub(crate) fn pause(&mut self) {
        self.running = false;
    }

    /// True while running.
    pub(crate) fn is_running(&self) -> bool {
        self.running
    }

    /// Does one generation's worth of evaluations (the population size, at least one unit),
    /// paused or not, and reports.
    pub(crate) fn step_once(&mut self) -> Result<Progress, String> {
        self.reproduction = None;
        let evaluations = self.config.params.population.max(1) as u64;
        let optimizer = self.ensure_optimizer(false)?;
        let was_done = optimizer.progress().done;
        let p = optimizer.step(evaluations);
        self.revision += 1;
        if p.done && !was_done {
            self.select_at_run_end();
        }
        Ok(p)
    }

    /// Runs the optimizer for one frame: repeated small `step` calls until `clock()` (in ms) says
    /// `budget_ms` has passed, the next call would likely end past it, or the algorithm is done.
    /// Does nothing when paused; otherwise makes at least one call. The chunk size adapts so one
    /// call takes about a tenth of the budget, and a call never spends more than one unit beyond
    /// its chunk (for the genetic algorithms a unit is one evaluation). A call is not started
    /// when the slowest evaluation seen in this frame, times the chunk, would not fit in what is
    /// left of the budget: evaluations of dense meshes cost several times those of sparse ones,
    /// so stopping only once the budget is gone would let the last call run well past it. Nor
    /// is one started when the longest call of recent frames would not fit: some units cost far
    /// more than their evaluations say (a fresh build of a large mesh is one evaluation), and
    /// they come back every few frames.
    pub(crate) fn tick(&mut self, budget_ms: f64, clock: &mut dyn FnMut() -> f64) -> TickReport {
        let mut report = TickReport::default();
        if !self.running {
            self.pool_clock = None;
            return report;
        }
        let Some(optimizer) = self.optimizer.as_mut() else {
            self.running = false;
            return report;
        };
        if optimizer.as_any().is_some_and(|a| a.is::<PoolRun>()) {
            // The workers do the work; the frame only counts the time.
            let now = clock();
            if let Some(last) = self.pool_clock.replace(now) {
                self.elapsed_ms += now - last;
            }
            report.steps = 1;
            return report;
        }
        let start = clock();
        self.slowest_call_ms *= SLOW_CALL_FADE;
        let before = optimizer.progress().evaluations;
        let mut now = start;
        // The slowest evaluation of this frame so far, in ms.
        let mut slowest_eval: f64 = 0.0;
        let mut finished = false;
        loop {
            let call_start = now;
            let evals_before = optimizer.progress().evaluations;
            let p = match self.reproduction {
                Some(r) => optimizer.step_until(self.chunk, r.generations),
                None => optimizer.step(self.chunk),
            };
            now = clock();
            report.steps += 1;
            let spent = p.evaluations - evals_before;
            let took = now - call_start;
            self.slowest_call_ms = self.slowest_call_ms.max(took);
            // Aim for a tenth of the budget per call so the last call overshoots little. The
            // chunk at most doubles per call: a call faster than the timer's resolution
            // (performance.now() is coarsened) must not make the next call run away.
            if spent > 0 {
                let per_eval = (took / spent as f64).max(1e-6);
                slowest_eval = slowest_eval.max(per_eval);
                let target = (budget_ms / 10.0 / per_eval).floor();
                self.chunk = target.clamp(1.0, 2.0 * self.chunk as f64) as u64;
            }
            if p.done {
                self.running = false;
            }
            finished |= p.done;
            if let Some(r) = self.reproduction
                && (p.done || p.generation >= r.generations)
            {
                self.running = false;
                self.reproduction = None;
                if let Some(i) = r.selected {
                    self.selected = optimizer.front().solutions().get(i).cloned();
                }
                self.revision += 1;
            }
            // A pool run's step only reads its workers' reports; so does a step that found
            // nothing left to do.
            if !self.running || spent == 0 {
                break;
            }
            let expected_next = (slowest_eval * self.chunk as f64).max(self.slowest_call_ms);
            if now - start + expected_next > budget_ms {
                break;
            }
        }
        report.evaluations = optimizer.progress().evaluations - before;
        self.elapsed_ms += now - start;
        if report.evaluations > 0 {
            self.revision += 1;
        }
        // After a shared run's own selection was applied, so that one wins.
        if finished {
            self.select_at_run_end();
        }
        report
    }

    /// The status line's numbers.
    pub(crate) fn status(&self) -> Status {
        let Some(optimizer) = self.optimizer.as_ref() else {
            return Status::default();
        };
        let p = optimizer.progress();
        Status {
            generation: p.generation,
            evaluations: p.evaluations,
            evaluations_per_second: if self.elapsed_ms > 0.0 {
                p.evaluations as f64 / (self.elapsed_ms / 1000.0)
            } else {
                0.0
            },
            front_size: optimizer.front().len(),
            elapsed_ms: self.elapsed_ms,
            done: p.done,
        }
    }

    /// The archive front (empty before the first run).
    pub(crate) fn front(&self) -> Option<&Front> {
        self.optimizer.as_ref().map(|o| o.front())
    }

    /// The running algorithm, for views that show more than the front (the population and its
    /// ranks).
    pub(crate) fn optimizer(&self) -> Option<&dyn Running> {
        self.optimizer.as_deref()
    }

    /// A counter that changes whenever what the views show may have changed.
    pub(crate) fn revision(&self) -> u64 {
        self.revision
    }

    /// The selected solution, if any (it stays selected when it later leaves the front).
    pub(crate) fn selected(&self) -> Option<&Solution> {
        self.selected.as_ref()
    }

    /// Selects the front member at `index` (by increasing T). Out of range clears the selection.
    pub(crate) fn select_front_index(&mut self, index: Option<usize>) {
        let chosen = index.and_then(|i| self.front().and_then(|f| f.solutions().get(i).cloned()));
        self.selected = chosen;
        self.revision += 1;
    }

    /// Selects `solution`, which need not be on this app's front (compare mode selects members
    /// of the other methods' fronts); `None` clears the selection.
    pub(crate) fn select_solution(&mut self, solution: Option<Solution>) {
        self.selected = solution;
        self.revision += 1;
    }

    /// Selects the front's knee ([`crate::pick::knee`]) when nothing is selected: a choice of
    /// the user's or a share link's always wins.
    fn select_at_run_end(&mut self) {
        if self.selected.is_none() {
            self.select_by(Pick::Knee);
        }
    }

    /// Selects the member of the current front that `rule` picks (the trade-off pick's weights
    /// drawn with the run's seed); returns whether a member was found.
    pub(crate) fn select_by(&mut self, rule: Pick) -> bool {
        let Some(front) = self.front() else {
            return false;
        };
        let grid_points = self.surface.heightfield.len();
        let Ok(chosen) = pick_in_front(front, rule, self.config.params.seed, grid_points) else {
            return false;
        };
        let chosen = chosen.clone();
        if Some(&chosen) != self.selected.as_ref() {
            self.selected = Some(chosen);
            self.revision += 1;
        }
        true
    }

    /// Selects `solution` (a compare run's trade-off pick, say) unless something is selected
    /// already; returns whether it did.
    pub(crate) fn select_if_unselected(&mut self, solution: Solution) -> bool {
        if self.selected.is_some() {
            return false;
        }
        self.select_solution(Some(solution));
        true
    }

    /// Index in the current front of the selected solution (matched by its objectives).
    pub(crate) fn selected_front_index(&self) -> Option<usize> {
        let s = self.selected.as_ref()?;
        self.front()?
            .solutions()
            .iter()
            .position(|m| m.objectives() == s.objectives())
    }

    /// Moves the selection `delta` members along the front (clamped to its ends). With nothing
    /// selected, selects the first member (fewest triangles) for a step right and the last one
    /// for a step left.
    pub(crate) fn move_selection(&mut self, delta: isize) {
        let Some(len) = self.front().map(|f| f.len()).filter(|&n| n > 0) else {
            return;
        };
        let last = len as isize - 1;
        let next = match (self.selected_front_index(), self.selected.as_ref()) {
            (Some(i), _) => (i as isize + delta).clamp(0, last),
            // The selection left the front: start from the member nearest in T.
            (None, Some(s)) => {
                let front = self.front().expect("len > 0");
                let at = front.solutions().partition_point(|m| m.t < s.t);
                (at as isize + delta.min(0)).clamp(0, last)
            }
            (None, None) if delta >= 0 => 0,
            (None, None) => last,
        } as usize;
        self.select_front_index(Some(next));
    }

    /// The kept set to show: the selection's, or every grid point (the full-resolution mesh)
    /// when nothing is selected.
    pub(crate) fn shown_kept(&self) -> Vec<u32> {
        match &self.selected {
            Some(s) => s.kept.clone(),
            None => (0..self.surface.heightfield.len() as u32).collect(),
        }
    }
}

/// Triangles and per-grid-point error of one kept set, for the 3-D view and the exports.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ShownMesh {
    /// Kept grid indices, increasing, corners included.
    pub kept: Vec<u32>,
    /// Triangles as grid-index triples, counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// |z − z̃| at every grid point.
    pub point_error: Vec<f64>,
    /// Σ|z − z̃|.
    pub e_sum: f64,
}

/// Triangulates `kept` on `hf` like the evaluator and measures the error at every grid point.
pub(crate) fn shown_mesh(hf: &Arc<Heightfield>, kept: &[u32]) -> Result<ShownMesh, String> {
    let mut evaluator = Evaluator::new(hf.clone());
    let evaluation = evaluator.evaluate(kept).map_err(|e| e.to_string())?;
    Ok(shown_triangles(
        hf,
        evaluator.kept().to_vec(),
        evaluation.triangles,
        evaluation.score.e_sum,
    ))
}

/// The mesh of `triangles` over the kept points `kept` (E_sum `e_sum`) with the error at
/// every grid point.
pub(crate) fn shown_triangles(
    hf: &Heightfield,
    kept: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    e_sum: f64,
) -> ShownMesh {
    let grid = crate::evaluator::raster::Grid {
        width: hf.width() as i64,
        height: hf.height() as i64,
        z: hf.z(),
    };
    let lattice = Lattice::new(hf.width());
    let mut point_error = vec![0.0; hf.len()];
    for tri in &triangles {
        let p = tri.map(|i| lattice.point(i));
        grid.for_each_point(p, |index, interpolated| {
            point_error[index] = (hf.z()[index] - interpolated).abs();
        });
    }
    ShownMesh {
        kept,
        triangles,
        point_error,
        e_sum,
    }
}
