//! The evolutionary algorithms and their operators: NSGA-II, orthogonal-array crossover, the
//! weighted-sum GA.
//!
//! - [`chromosome`]: the bitset of kept grid points.
//! - `operators`: initialisation, bit-flip mutation, uniform and two-point crossover.
//! - `orthogonal_array` and [`oax`]: orthogonal-array crossover (Huang & Ho 2003).
//! - `ranking`: non-dominated sorting and crowding distance.
//! - `scalarisation`: the normalised weighted sum of E and T, the scalar fitness.
//! - `scorer`: scores chromosomes, reusing the meshes of those scored before.
//! - `nsga2`: NSGA-II (Deb et al. 2002).
//! - [`trace`]: what one NSGA-II generation did, phase by phase (for the teaching view).
//! - `weighted_sum`: the weighted-sum single-objective GA, one run per weight.
//! - [`memetic`]: the memetic NSGA-II (greedy seeding, guided operators, local search).

pub mod chromosome;
mod mating;
pub mod memetic;
pub(crate) mod nsga2;
pub mod oax;
pub(crate) mod operators;
pub(crate) mod orthogonal_array;
pub(crate) mod params;
pub(crate) mod ranking;
pub(crate) mod scalarisation;
pub(crate) mod scorer;
pub mod trace;
pub(crate) mod weighted_sum;

// On real terrain: determinism, slicing invariance, non-dominated fronts, honest objectives.
#[cfg(test)]
mod tests;

pub use memetic::{Memetic, MemeticParams};
pub use nsga2::{Individual, Nsga2};
pub use operators::CrossoverKind;
pub use params::{GaParams, ParamsError};
pub(crate) use weighted_sum::{WeightedSum, WeightedSumParams};
