//! Parameters of the memetic algorithm. They are serialised into front.json, so every field
//! has a stable name.

use super::decimation::start_triangles;
use super::seeding::densest_seed;
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Parameters of [`Memetic`](super::Memetic).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MemeticParams {
    /// Population size μ (also the offspring per generation).
    pub population: usize,
    /// Probability that a child is a crossover of two neighbours in T (else a copy of one
    /// parent), before its guided mutation.
    pub crossover_probability: f64,
    /// Local-search units after each generation's offspring, at least (see
    /// `LOCAL_SEARCH_SHARE`).
    pub local_search_rounds: usize,
    /// Stop once this many evaluations were spent (checked between units of work); `None` =
    /// [`seeding_budget`] plus [`search_evaluations`](Self::search_evaluations) of the grid.
    pub max_evaluations: Option<u64>,
    /// When [`max_evaluations`](Self::max_evaluations) is not set, the evaluations after
    /// seeding (the evolution's and the local search's); `None` = `search_budget` of the
    /// grid. A tile of a tiled run gets its share of the whole grid's
    /// (the catalogue's `Config::tile_share`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search_evaluations: Option<u64>,
    /// Seed from the greedy sweeps (`seeding`); when off, the initial
    /// population is random kept sets at log-spaced densities (an ablation).
    #[serde(skip_serializing_if = "is_on")]
    pub greedy_seeding: bool,
    /// Mutate with the error-guided operators (`mutation`); when off, a
    /// child flips one random grid point in or out (an ablation).
    #[serde(skip_serializing_if = "is_on")]
    pub guided_mutation: bool,
    /// Draw a crossover mate among the neighbours in T
    /// (`neighbour_mating`); when off, any other member (an
    /// ablation).
    #[serde(skip_serializing_if = "is_on")]
    pub neighbour_mating: bool,
    /// Run the local search after each generation (`local_search`);
    /// when off, generations are offspring and survival only (an ablation).
    #[serde(skip_serializing_if = "is_on")]
    pub local_search: bool,
    /// The error the run minimises beside T: its selection, archive, decimation costs and local
    /// search compare in it. Written only when not `sum`, so a default run's front.json reads
    /// as before measures existed.
    #[serde(skip_serializing_if = "ErrorMeasure::is_sum")]
    pub error: ErrorMeasure,
}

/// The component switches are written only when off, so the full method's parameters (and its
/// front.json) read as before the switches existed.
fn is_on(switch: &bool) -> bool {
    *switch
}

impl Default for MemeticParams {
    fn default() -> Self {
        Self {
            population: 24,
            crossover_probability: 0.3,
            local_search_rounds: 24,
            max_evaluations: None,
            search_evaluations: None,
            greedy_seeding: true,
            guided_mutation: true,
            neighbour_mating: true,
            local_search: true,
            error: ErrorMeasure::Sum,
        }
    }
}

/// The default evaluation budget on `hf`: the two seeding sweeps (one evaluation per point
/// they insert: every grid point, then half as many as the densest seed has triangles,
/// `densest_seed`), the decimation (`DECIMATION_EVALUATIONS` per triangle of the mesh it
/// starts from, `start_triangles`), then the search ([`search_budget`]).
/// docs/performance.md gives what it costs on grids of several sizes.
pub(crate) fn default_budget(hf: &Heightfield) -> u64 {
    seeding_budget(hf) + search_budget(hf.len() as u64)
}

/// The evolution's and the local search's evaluations on a grid of `points` points:
/// `SEARCH_EVALUATIONS` plus one per grid point, up to `SEARCH_GRID_CAP` of them. The
/// search grows with the grid because the front has more to improve on a larger one, but more
/// slowly than the grid beyond `SEARCH_GRID_CAP` points: there each evaluation costs more
/// (its mesh is larger), so a search that grew with the grid would make the run grow faster
/// than the sweeps do.
pub(crate) fn search_budget(points: u64) -> u64 {
    SEARCH_EVALUATIONS + points.min(SEARCH_GRID_CAP)
}

/// The part of `default_budget` that the seeding sweeps and the decimation take (an
/// estimate: the decimation's count depends on the surface).
pub fn seeding_budget(hf: &Heightfield) -> u64 {
    hf.len() as u64
        + densest_seed(hf) as u64 / 2
        + DECIMATION_EVALUATIONS * start_triangles(hf) as u64
}

/// See [`default_budget`]: a decimation costs about 3.8 evaluations per triangle of its start
/// mesh (a first cost per vertex, then a removal and its neighbours' new costs).
pub(crate) const DECIMATION_EVALUATIONS: u64 = 4;

/// See [`default_budget`]: the search's floor, which on a small grid (where evaluations are
/// cheap) is most of it. The sparsest meshes need it most: each of their points carries much
/// of the error, so a few good moves change E the most.
pub(crate) const SEARCH_EVALUATIONS: u64 = 120_000;

/// See [`default_budget`]: 2¹⁷, twice a 257×257 grid, so grids up to that size search as
/// long as ever, and larger ones search at most 251 072 evaluations.
pub(crate) const SEARCH_GRID_CAP: u64 = 1 << 17;

/// Why a set of parameters cannot run.
#[derive(Clone, Debug, PartialEq)]
pub enum MemeticParamsError {
    /// The population is smaller than 2 (a mating needs two parents).
    PopulationTooSmall(usize),
    /// The crossover probability is not in [0, 1].
    BadProbability(f64),
}

impl fmt::Display for MemeticParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::PopulationTooSmall(n) => {
                write!(f, "the population must hold at least 2 members, not {n}")
            }
            Self::BadProbability(p) => {
                write!(f, "the crossover probability must be in [0, 1], not {p}")
            }
        }
    }
}

impl std::error::Error for MemeticParamsError {}

impl MemeticParams {
    /// Checks the ranges.
    pub(crate) fn validate(&self) -> Result<(), MemeticParamsError> {
        if self.population < 2 {
            return Err(MemeticParamsError::PopulationTooSmall(self.population));
        }
        if !(0.0..=1.0).contains(&self.crossover_probability) {
            return Err(MemeticParamsError::BadProbability(
                self.crossover_probability,
            ));
        }
        Ok(())
    }

    /// The evaluation budget on `hf`.
    pub(crate) fn budget(&self, hf: &Heightfield) -> u64 {
        self.max_evaluations
            .unwrap_or_else(|| match self.search_evaluations {
                Some(search) => seeding_budget(hf) + search,
                None => default_budget(hf),
            })
    }
}
