//! The memetic NSGA-II, ParetoMesh's own method: NSGA-II's sorting, crowding, elitist survival
//! and archive, with operators that know the geometry and a local search that polishes the
//! front.
//!
//! - `seeding`: the initial population from two greedy-insertion sweeps (max-error rule and
//!   worst point of the largest-error-sum triangle); the mix is documented there.
//! - `decimation`: exact-cost decimation of a dense greedy mesh, whose recordings join the
//!   archive and the seeds.
//! - `mutation`: error-guided insertion, removal and vertex moves, each a local edit scored
//!   incrementally ([`Evaluator::edit`](crate::evaluator::Evaluator::edit),
//!   `Evaluator::score_mutant`).
//! - `neighbour_mating`: crossover between parents of similar T.
//! - `local_search`: swap moves at fixed T on archive members, spread over the front.
//! - `guide`: the per-triangle errors and per-vertex removal costs the operators read.
//! - `member`: a scored kept set with its mesh, and the edits made to it. Members that wait
//!   for their next use are stowed: their meshes lend their per-grid-point arrays to the few
//!   being edited (`member::LookupPool`), so a member's memory grows with its mesh, not with
//!   the grid.
//! - `optimizer`: the loop.
//!
//! A generation: μ children (each a copy of a tournament winner or, with the crossover
//! probability, its crossover with a neighbour in T; then one guided mutation drawn among the
//! three), (μ + λ) survival, then [`MemeticParams::local_search_rounds`] local-search units,
//! and more until the local search has spent its share of the evaluations
//! (`LOCAL_SEARCH_SHARE`).
//! Every evaluated kept set is offered to the archive ([`Optimizer::front`]), which starts as
//! both greedy fronts and the decimation's recordings.
//!
//! Each component can be switched off in [`MemeticParams`] (greedy seeding, guided mutation,
//! mating among neighbours, local search), so that an experiment can measure what each one
//! adds; the unguided replacements are random kept sets at log-spaced densities, a random
//! point flip, and a random mate.
//!
//! Every random draw comes from one generator seeded by the run's seed, in an order fixed by
//! the units, and the state only changes a whole unit at a time, so a seed reproduces a run
//! exactly however the work is sliced into steps.
//!
//! [`Optimizer::front`]: crate::optimizer::Optimizer::front

pub(crate) mod decimation;
pub(crate) mod guide;
pub(crate) mod local_search;
pub(crate) mod member;
pub(crate) mod mutation;
pub(crate) mod neighbour_mating;
pub(crate) mod optimizer;
pub(crate) mod params;
pub(crate) mod seeding;
#[cfg(test)]
mod tests;

pub use optimizer::Memetic;
pub(crate) use params::search_budget;
pub use params::{MemeticParams, MemeticParamsError, seeding_budget};
