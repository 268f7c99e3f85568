//! A run done off the page's thread by a pool of Web Workers: the page's side of it, free of
//! the DOM so it is tested natively.
//!
//! The run is cut into jobs: the whole grid as one job when it is untiled, else one job per
//! tile. The page hands each free worker the next job ([`PoolRun::next_job`]) with only that
//! job's heights; a worker posts the job's front as it grows ([`PoolRun::report`]) or a failure
//! ([`PoolRun::fail`]). [`PoolRun`] is an [`Optimizer`] whose work happens elsewhere: stepping it
//! only reads what the workers reported, so the app's frame loop, status line, plot, selection
//! and exports treat it like an optimizer running on the page. Every job is a pure function of
//! its inputs, so the front does not depend on how many workers ran it.

use super::algorithms::{Algorithm, Params, Running};
use super::tiled_run::{TileJob, TiledRun};
use crate::front::{Front, Solution};
use crate::optimizer::{Optimizer, Progress};
use crate::tiling::{DEFAULT_TILE, TileFront, TilePlan};

/// How a pool run is set up: the page knows the workers, the app the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PoolSetup {
    /// Workers to start (the page uses `navigator.hardwareConcurrency`), at least one.
    pub workers: usize,
    /// Run grids that fit in one tile in the pool too (the page's `?workers` flag), instead of
    /// in the frame loop.
    pub always: bool,
    /// The largest tile side: a grid with a longer side is cut into tiles (the page's
    /// `?tile=N`, else [`DEFAULT_TILE`], the CLI's default).
    pub tile: usize,
}

impl Default for PoolSetup {
    fn default() -> Self {
        Self {
            workers: 1,
            always: false,
            tile: DEFAULT_TILE,
        }
    }
}

/// What a worker is handed: which run, which job, what to run.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Job {
    /// The run it belongs to (a report for another run is stale and ignored).
    pub run: u64,
    /// Its index among the run's jobs.
    pub index: usize,
    /// What the job runs.
    pub work: Work,
}

/// What a job runs.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Work {
    /// The algorithm on the whole grid, posting its front as it grows.
    Whole {
        /// The algorithm.
        algorithm: Algorithm,
        /// Its parameters.
        params: Params,
    },
    /// One tile's run (see [`crate::tiling::run_tile`]), posting the tile's front at its end.
    Tile(TileJob),
}

/// The jobs of a run: the whole grid, or its tiles.
enum Jobs {
    /// The whole grid in one job, with its front and progress as last reported.
    Whole {
        algorithm: Algorithm,
        params: Params,
        front: Front,
        progress: Progress,
    },
    /// The grid's tiles, with the whole-grid front assembled from their fronts.
    Tiled { run: TiledRun, front: Front },
}

/// The state of a pool run on the page.
pub(crate) struct PoolRun {
    id: u64,
    jobs: Jobs,
    /// Per job: whether its worker said it is finished.
    finished: Vec<bool>,
    handed_out: usize,
    failure: Option<String>,
}

impl PoolRun {
    /// Run `id` of `algorithm` with `params`: on the whole grid in one job when `plan` is
    /// `None`, else one job per tile of `plan` and pass (see [`TiledRun`]).
    pub(crate) fn new(
        id: u64,
        algorithm: Algorithm,
        params: Params,
        plan: Option<TilePlan>,
    ) -> Result<Self, String> {
        params.validate()?;
        let jobs = match plan {
            None => Jobs::Whole {
                algorithm,
                params,
                front: Front::default(),
                progress: Progress {
                    evaluations: 0,
                    generation: 0,
                    done: false,
                },
            },
            Some(plan) => Jobs::Tiled {
                run: TiledRun::new(plan, algorithm, params),
                front: Front::default(),
            },
        };
        let count = match &jobs {
            Jobs::Whole { .. } => 1,
            Jobs::Tiled { run, .. } => run.job_count(),
        };
        Ok(Self {
            id,
            jobs,
            finished: vec![false; count],
            handed_out: 0,
            failure: None,
        })
    }

    /// The run's id.
    pub(crate) fn id(&self) -> u64 {
        self.id
    }

    /// Jobs the run is cut into.
    pub(crate) fn job_count(&self) -> usize {
        self.finished.len()
    }

    /// Jobs whose worker has said they are finished.
    pub(crate) fn jobs_done(&self) -> usize {
        self.finished.iter().filter(|&&f| f).count()
    }

    /// The tiles of a tiled run.
    pub(crate) fn tiled(&self) -> Option<&TiledRun> {
        match &self.jobs {
            Jobs::Tiled { run, .. } => Some(run),
            Jobs::Whole { .. } => None,
        }
    }

    /// The next job for a free worker, in index order; `None` once every job was handed out or
    /// the run failed.
    pub(crate) fn next_job(&mut self) -> Option<Job> {
        if self.failure.is_some() || self.handed_out == self.job_count() {
            return None;
        }
        let index = self.handed_out;
        self.handed_out += 1;
        let work = match &self.jobs {
            Jobs::Whole {
                algorithm, params, ..
            } => Work::Whole {
                algorithm: *algorithm,
                params: params.clone(),
            },
            Jobs::Tiled { run, .. } => Work::Tile(run.job(index)?),
        };
        Some(Job {
            run: self.id,
            index,
            work,
        })
    }

    /// The finished flag of job `index` of run `run`; `None` for a stale report (another run,
    /// or a run that already failed).
    fn slot(&mut self, run: u64, index: usize) -> Result<Option<&mut bool>, String> {
        if run != self.id || self.failure.is_some() {
            return Ok(None);
        }
        self.finished
            .get_mut(index)
            .map(Some)
            .ok_or_else(|| format!("a worker reported job {index} of a run with fewer jobs"))
    }

    /// A worker reports the whole-grid job `index` of run `run`: its front so far and its
    /// progress. Reports of another run are ignored (a worker of a run the user left may still
    /// post); a report that does not fit the run is an error for the user. Returns whether the
    /// front changed.
    pub(crate) fn report(
        &mut self,
        run: u64,
        index: usize,
        front: Front,
        progress: Progress,
    ) -> Result<bool, String> {
        let Some(finished) = self.slot(run, index)? else {
            return Ok(false);
        };
        *finished = progress.done;
        match &mut self.jobs {
            Jobs::Whole {
                front: f,
                progress: p,
                ..
            } => {
                *f = front;
                *p = progress;
                Ok(true)
            }
            Jobs::Tiled { .. } => Err("a worker posted a whole-grid front for a tile".to_string()),
        }
    }

    /// A worker reports the tile job `index` of run `run` done with the tile's front. Returns
    /// whether the whole-grid front changed; see [`PoolRun::report`] for stale reports.
    pub(crate) fn report_tile(
        &mut self,
        run: u64,
        index: usize,
        front: TileFront,
    ) -> Result<bool, String> {
        let Some(finished) = self.slot(run, index)? else {
            return Ok(false);
        };
        *finished = true;
        match &mut self.jobs {
            Jobs::Tiled { run, front: whole } => {
                let changed = run.report(index, front)?;
                if changed {
                    *whole = run.front();
                }
                Ok(changed)
            }
            Jobs::Whole { .. } => {
                Err("a worker posted a tile's front for an untiled run".to_string())
            }
        }
    }

    /// A worker failed on job `index` of run `run` with `message` (`None`: the page could not
    /// hand a job out): the run stops and the message is shown. Reports of another run are
    /// ignored.
    pub(crate) fn fail(&mut self, run: u64, index: Option<usize>, message: &str) {
        if run == self.id && self.failure.is_none() {
            self.failure = Some(match index {
                Some(i) => format!(
                    "a worker failed on job {i} of {}: {message}",
                    self.job_count()
                ),
                None => format!("a job could not be handed to a worker: {message}"),
            });
        }
    }

    /// Why the run stopped, when a worker failed.
    pub(crate) fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }
}

impl Optimizer for PoolRun {
    /// Nothing: a pool run advances only by its workers' reports.
    fn unit(&mut self) {}

    fn step(&mut self, _max_evaluations: u64) -> Progress {
        self.progress()
    }

    fn step_until(&mut self, _max_evaluations: u64, _generation: u64) -> Progress {
        self.progress()
    }

    fn run_to_end(&mut self) -> Progress {
        self.progress()
    }

    fn front(&self) -> &Front {
        match &self.jobs {
            Jobs::Whole { front, .. } | Jobs::Tiled { front, .. } => front,
        }
    }

    /// The whole-grid job's progress, or for a tiled run the evaluations of the tiles' fronts
    /// and, as generations, the passes completed; done when every job is (or when a worker
    /// failed, which ends the run).
    fn progress(&self) -> Progress {
        let done = self.failure.is_some() || self.jobs_done() == self.job_count();
        match &self.jobs {
            Jobs::Whole { progress, .. } => Progress {
                done: done || progress.done,
                ..*progress
            },
            Jobs::Tiled { run, .. } => Progress {
                evaluations: run.evaluations(),
                generation: (self.jobs_done() / run.plan().len()) as u64,
                done,
            },
        }
    }
}

impl Running for PoolRun {
    fn as_any_mut(&mut self) -> Option<&mut dyn std::any::Any> {
        Some(self)
    }
    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }
}

/// A front packed into flat arrays, the form in which a worker posts it to the page (the arrays
/// travel as transferables, so a front of millions of kept indices costs the page no parsing).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct FrontParts {
    /// E_sum, E_max and T of each member, in the front's order.
    pub scores: Vec<f64>,
    /// Where each member's kept indices start in `kept`, with the end as a last entry.
    pub offsets: Vec<u32>,
    /// Every member's kept indices, one after another.
    pub kept: Vec<u32>,
}

impl FrontParts {
    /// Packs `front`.
    pub(crate) fn of(front: &Front) -> Self {
        let mut parts = FrontParts {
            scores: Vec::with_capacity(3 * front.len()),
            offsets: Vec::with_capacity(front.len() + 1),
            kept: Vec::new(),
        };
        parts.offsets.push(0);
        for s in front.solutions() {
            parts.scores.extend([s.e_sum, s.e_max, s.t as f64]);
            parts.kept.extend_from_slice(&s.kept);
            parts.offsets.push(parts.kept.len() as u32);
        }
        parts
    }

    /// Unpacks the front, checking that the arrays fit each other and that it is a front
    /// (sorted by increasing T, each member better in E than the one before): the arrays come
    /// from another thread.
    pub(crate) fn into_front(self) -> Result<Front, String> {
        let members = self.scores.len() / 3;
        if !self.scores.len().is_multiple_of(3)
            || self.offsets.len() != members + 1
            || self.offsets.first() != Some(&0)
            || self.offsets.last().map(|&o| o as usize) != Some(self.kept.len())
            || self.offsets.windows(2).any(|w| w[0] > w[1])
        {
            return Err("a worker posted a front whose arrays do not fit each other".to_string());
        }
        let solutions: Vec<Solution> = (0..members)
            .map(|i| {
                let [e_sum, e_max, t] = [0, 1, 2].map(|k| self.scores[3 * i + k]);
                let kept =
                    self.kept[self.offsets[i] as usize..self.offsets[i + 1] as usize].to_vec();
                Solution::recorded(e_sum, e_max, t as usize, kept)
            })
            .collect();
        let front = Front::merged(&solutions);
        if front.len() != members {
            return Err("a worker posted members that are not a front".to_string());
        }
        Ok(front)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn front(points: &[(f64, usize)]) -> Front {
        Front::merged(
            &points
                .iter()
                .map(|&(e, t)| Solution::recorded(e, e / 2.0, t, (0..t as u32 + 2).collect()))
                .collect::<Vec<_>>(),
        )
    }

    fn progress(evaluations: u64, done: bool) -> Progress {
        Progress {
            evaluations,
            generation: evaluations / 10,
            done,
        }
    }

    #[test]
    fn front_parts_round_trip() {
        let f = front(&[(10.0, 2), (4.0, 6), (3.0, 9)]);
        let parts = FrontParts::of(&f);
        assert_eq!(parts.offsets, vec![0, 4, 12, 23]);
        assert_eq!(parts.into_front().unwrap(), f);
        let empty = FrontParts::of(&Front::default());
        assert_eq!(empty.offsets, vec![0]);
        assert_eq!(empty.into_front().unwrap(), Front::default());
    }

    #[test]
    fn front_parts_that_do_not_fit_are_refused() {
        let mut parts = FrontParts::of(&front(&[(10.0, 2), (4.0, 6)]));
        parts.offsets[2] += 1;
        assert!(
            parts
                .clone()
                .into_front()
                .unwrap_err()
                .contains("do not fit")
        );
        parts.offsets[2] -= 1;
        parts.scores[3] = 11.0; // the second member is now dominated
        assert!(parts.into_front().unwrap_err().contains("not a front"));
    }

    #[test]
    fn jobs_are_handed_out_once_in_order() {
        let mut run = PoolRun::new(
            7,
            Algorithm::Memetic,
            Params::default(),
            Some(TilePlan::new(100, 40, 40).unwrap()),
        )
        .unwrap();
        let indices: Vec<_> = std::iter::from_fn(|| run.next_job())
            .map(|j| (j.run, j.index))
            .collect();
        // Three tiles, two passes: greedy insertion first, then the chosen method.
        assert_eq!(indices, (0..6).map(|i| (7, i)).collect::<Vec<_>>());
    }

    #[test]
    fn an_untiled_run_shows_its_one_jobs_front_and_ends_with_it() {
        let mut run = PoolRun::new(1, Algorithm::Memetic, Params::default(), None).unwrap();
        assert!(!run.step(100).done);
        let early = front(&[(10.0, 2)]);
        assert!(
            run.report(1, 0, early.clone(), progress(50, false))
                .unwrap()
        );
        assert_eq!(run.front(), &early);
        assert_eq!(run.step(100), progress(50, false));
        let last = front(&[(10.0, 2), (4.0, 6)]);
        run.report(1, 0, last.clone(), progress(90, true)).unwrap();
        assert_eq!(run.front(), &last);
        assert!(run.progress().done);
        assert_eq!(run.jobs_done(), 1);
    }

    #[test]
    fn stale_reports_are_ignored_and_bad_ones_refused() {
        let mut run = PoolRun::new(2, Algorithm::Memetic, Params::default(), None).unwrap();
        assert!(
            !run.report(1, 0, front(&[(1.0, 2)]), progress(5, true))
                .unwrap()
        );
        assert!(run.front().is_empty());
        assert_eq!(
            run.report(2, 3, front(&[(1.0, 2)]), progress(5, true)),
            Err("a worker reported job 3 of a run with fewer jobs".to_string())
        );
        run.fail(1, Some(0), "old");
        assert!(run.failure().is_none());
    }

    #[test]
    fn a_failed_worker_ends_the_run_with_its_message() {
        let mut run = PoolRun::new(3, Algorithm::Memetic, Params::default(), None).unwrap();
        run.next_job();
        run.fail(3, Some(0), "out of memory");
        assert!(run.progress().done);
        assert_eq!(
            run.failure(),
            Some("a worker failed on job 0 of 1: out of memory")
        );
        assert!(run.next_job().is_none());
        assert!(
            !run.report(3, 1, front(&[(1.0, 2)]), progress(5, true))
                .unwrap()
        );
    }
}
