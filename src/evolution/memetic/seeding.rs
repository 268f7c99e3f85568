//! The initial population, from two greedy-insertion sweeps and the decimation of one.
//!
//! The mix: two greedy-insertion runs from the corners, one with the classic max-error rule
//! ([`InsertionRule::MaxError`]) to every grid point, and one that inserts the worst point of
//! the triangle with the largest error sum ([`InsertionRule::WorstTriangle`]), which suits a
//! sum-type error such as E_sum, to [`densest_seed`] triangles. Each records its mesh at
//! [`RECORDS`] geometrically spaced triangle counts (twice greedy insertion's default, so that
//! the seed front has no wide gaps in T). Every recorded mesh of both runs is offered to the
//! archive (so the final front weakly dominates both greedy fronts). Then the first run's mesh
//! at [`start_triangles`] is decimated by exact costs down to the corners
//! ([`decimation`](super::decimation)), each of its recordings offered to the archive too,
//! and the population takes μ [`seeds`] at evenly spaced positions of the
//! archive's members of at most [`densest_seed`] triangles (by increasing T, so evenly in
//! log T, from the sparsest mesh to half the decimation's start).
//!
//! Unit: one greedy insertion (one evaluation).

use super::decimation::start_triangles;
use crate::baselines::greedy_insertion::{
    GreedyInsertion, GreedyParams, GreedyStop, InsertionRule,
};
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;
use std::sync::Arc;

/// Recordings per seeding run.
pub(crate) const RECORDS: usize = 128;

/// The rules of the two seeding runs, in order.
pub(crate) const RULES: [InsertionRule; 2] =
    [InsertionRule::MaxError, InsertionRule::WorstTriangle];

/// The seeding runs in progress; see the module doc.
pub(crate) struct Seeding {
    hf: Arc<Heightfield>,
    /// The run in progress (index into [`RULES`]) and the runs' fronts once done.
    current: Option<(usize, Box<GreedyInsertion>)>,
    fronts: Vec<Front>,
    /// Insertions of the finished runs.
    finished_evaluations: u64,
    /// Recordings of the run in progress already handed out by [`unit`](Self::unit).
    handed_out: usize,
}

impl Seeding {
    /// Seeding on `hf`; nothing runs until the first unit.
    pub(crate) fn new(hf: Arc<Heightfield>) -> Self {
        Self {
            hf,
            current: None,
            fronts: Vec::new(),
            finished_evaluations: 0,
            handed_out: 0,
        }
    }

    /// Both runs finished?
    pub(crate) fn is_done(&self) -> bool {
        self.fronts.len() == RULES.len()
    }

    /// Insertions so far.
    pub(crate) fn evaluations(&self) -> u64 {
        self.finished_evaluations
            + self
                .current
                .as_ref()
                .map_or(0, |(_, run)| run.progress().evaluations)
    }

    /// One insertion (starting the next run when none is in progress). Hands each mesh the
    /// run records to `record` as soon as it is recorded, so a front shows from the first
    /// units on, however large the grid; every mesh of the runs' fronts passes through it, in
    /// the order the runs record them.
    pub(crate) fn unit(&mut self, mut record: impl FnMut(&Solution)) {
        if self.is_done() {
            return;
        }
        let next = self.fronts.len();
        let hf = self.hf.clone();
        let (_, run) = self.current.get_or_insert_with(|| {
            // The first run goes on to the full mesh, so the archive spans the whole front;
            // the second stops at the densest seed, past which it adds nothing the first does
            // not.
            let stop = if next == 0 {
                GreedyStop::AllPoints
            } else {
                GreedyStop::Triangles(densest_seed(&hf))
            };
            let params = GreedyParams {
                rule: RULES[next],
                records: RECORDS,
                stop,
                ..GreedyParams::default()
            };
            (
                next,
                Box::new(GreedyInsertion::new(hf, params).expect("default parameters are valid")),
            )
        });
        run.unit();
        for s in &run.recorded()[self.handed_out..] {
            record(s);
        }
        self.handed_out = run.recorded().len();
        if !run.progress().done {
            return;
        }
        self.finished_evaluations += run.progress().evaluations;
        self.fronts.push(run.front().clone());
        self.current = None;
        self.handed_out = 0;
    }

    /// The kept set [`decimation`](super::decimation) starts from: the first run's recorded
    /// mesh with the most triangles up to `triangles` (its sparsest one when none is that
    /// sparse). Both runs must be done.
    pub(crate) fn decimation_start(&self, triangles: usize) -> Vec<u32> {
        let front = &self.fronts[0];
        let start = front.within(triangles).or(front.solutions().first());
        start.expect("a run records its first mesh").kept.clone()
    }
}

/// The kept sets of `population` seeds (fewer when `front` has fewer members of at most
/// [`densest_seed`] triangles on `hf`), at evenly spaced positions of those members.
pub(crate) fn seeds(hf: &Heightfield, front: &Front, population: usize) -> Vec<Vec<u32>> {
    let all = front.solutions();
    // The front is sorted by increasing T.
    let members = &all[..all.partition_point(|s| s.t <= densest_seed(hf)).max(1)];
    spread(members.len(), population)
        .into_iter()
        .map(|index| members[index].kept.clone())
        .collect()
}

/// The most triangles a seed has: half the mesh the decimation starts from
/// ([`start_triangles`]), so a quarter of the full mesh up to a 257×257 grid, where the local
/// search's targets end too. Denser meshes have errors near zero, or (on a larger grid) come
/// from greedy insertion alone, while their meshes are the largest and every copy, guide and
/// trial on them costs in proportion (on a 1025×1025 grid a full mesh has 2 M triangles). The
/// archive still holds the sweeps' and the decimation's denser meshes.
pub(crate) fn densest_seed(hf: &Heightfield) -> usize {
    (start_triangles(hf) / 2).max(2)
}

/// min(`s`, `n`) distinct indices of 0..`n` at evenly spaced positions, round(j·(n−1)/(s−1)),
/// including both ends when at least two (the middle one for one).
pub(crate) fn spread(n: usize, s: usize) -> Vec<usize> {
    let s = s.min(n);
    match s {
        0 => Vec::new(),
        1 => vec![(n - 1) / 2],
        _ => (0..s)
            .map(|j| (2 * j * (n - 1) + (s - 1)) / (2 * (s - 1)))
            .collect(),
    }
}

/// `population` random kept sets, the unguided start the greedy seeds are measured against:
/// member j keeps the corners and random other points, n_j points in all, with n_j spaced
/// geometrically from 5 to every grid point (so the densities cover the front evenly in log T,
/// as the greedy seeds do). Each set is increasing.
pub(crate) fn random_seeds(
    hf: &Heightfield,
    population: usize,
    rng: &mut Pcg64Mcg,
) -> Vec<Vec<u32>> {
    let corners = hf.corners();
    let others: Vec<u32> = (0..hf.len() as u32)
        .filter(|i| !corners.contains(i))
        .collect();
    let (least, most) = (corners.len() as f64 + 1.0, hf.len() as f64);
    (0..population)
        .map(|j| {
            let share = if population > 1 {
                j as f64 / (population - 1) as f64
            } else {
                0.5
            };
            let points = (least.ln() + share * (most.ln() - least.ln()))
                .exp()
                .round() as usize;
            let extra = points.saturating_sub(corners.len()).min(others.len());
            // A partial Fisher–Yates shuffle over the non-corner points.
            let mut pool = others.clone();
            for k in 0..extra {
                let pick = rng.random_range(k..pool.len());
                pool.swap(k, pick);
            }
            let mut kept: Vec<u32> = corners
                .iter()
                .copied()
                .chain(pool[..extra].iter().copied())
                .collect();
            kept.sort_unstable();
            kept.dedup();
            kept
        })
        .collect()
}
