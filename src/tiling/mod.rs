//! Tiles: a large grid cut into tiles that share their border rows and columns, each tile
//! optimised on its own (on any thread or machine), and one whole-grid front assembled from
//! the tiles' fronts.
//!
//! **The mesh of a tiled grid** is the union of its tiles' canonical triangulations (an untiled
//! grid keeps the canonical Delaunay triangulation of its kept set). It is crack-free by
//! construction: every border line's vertices are fixed before optimisation from the line's
//! profile alone (`border`), the same from both sides, at one of a few nested border levels;
//! each tile keeps its corners and its border vertices, so its triangulation has the border
//! polyline as hull edges, and z̃ along a shared line is the same 1-D interpolation from both
//! sides: no cracks and no T-junctions. A line's points are then counted by one of its two
//! tiles only, so E_sum and T of the whole mesh are the sums of the tiles' shares, and E_max the
//! largest tile's.
//!
//! - `plan`: [`TilePlan`], the cut, and [`TilePlan::cut`], a tile's own grid;
//! - `border`: border lines ranked by 1-D greedy insertion, border levels;
//! - `algorithm`: a tile's method (the run's catalogue [`Config`](crate::catalogue::Config)
//!   with its tile share of the budget) and seed;
//! - `tile_front`: [`run_tile`], one tile's front, [`TileFront`];
//! - `allocation`: the multiple-choice allocation of one option per tile;
//! - `assemble`: [`assemble()`], the whole-grid front, [`TiledFront`];
//! - `mesh`: a whole-grid member's tile parts, kept points and triangles;
//! - `file`: front.json of a tiled run;
//! - `grow`: [`grow_tiled_member`], a member grown to a triangle budget by exact steps;
//! - `source`: [`TileSource`], where each tile's grid comes from: a whole grid in memory or
//!   windows of the grid file ([`GridWindows`](crate::import::GridWindows));
//! - `parallel` (native): [`run_tiled`] on a pool of threads;
//! - `within` (native): [`tiled_mesh_within`], one mesh within a max error, tiles in parallel.
//!
//! The files are private; what callers need is re-exported here.
//!
//! ```
//! use paretomesh::baselines::GreedyParams;
//! use paretomesh::catalogue::Config;
//! use paretomesh::heightfield::Heightfield;
//! use paretomesh::tiling::{TilePlan, assemble, run_tile};
//! let (w, h) = (70, 40);
//! let z = (0..w * h).map(|i| ((i % w) as f64 * 0.3).sin() + (i / w) as f64 * 0.05).collect();
//! let hf = Heightfield::new(w, h, z).unwrap();
//! let plan = TilePlan::new(w, h, 36).unwrap();
//! let greedy = Config::Greedy(GreedyParams { records: 16, ..GreedyParams::default() });
//! let fronts = (0..plan.len())
//!     .map(|i| run_tile(&plan.cut(&hf, i).unwrap(), &plan, i, &greedy, 1).unwrap())
//!     .collect();
//! let front = assemble(&plan, fronts).unwrap();
//! let mesh = front.mesh(&hf, 0).unwrap();
//! assert_eq!(mesh.triangles.len() as u64, front.members[0].t);
//! ```

mod algorithm;
mod allocation;
mod assemble;
mod border;
mod file;
mod grow;
#[cfg(test)]
mod measure_tests;
mod mesh;
#[cfg(not(target_arch = "wasm32"))]
mod parallel;
mod plan;
mod source;
#[cfg(test)]
mod test_fixtures;
#[cfg(test)]
mod tests;
mod tile_front;
#[cfg(not(target_arch = "wasm32"))]
mod within;

pub use algorithm::tile_config;
pub use assemble::{TiledFront, TiledMember, assemble};
pub use file::TiledFrontFile;
pub use grow::{TiledGrown, grow_tiled_member};
pub(crate) use mesh::{TilePart, TiledMesh, mesh_of_parts};
#[cfg(not(target_arch = "wasm32"))]
pub use parallel::{run_tiled, run_tiled_with_progress};
pub use plan::{DEFAULT_TILE, Tile, TilePlan, check_tile};
pub use source::TileSource;
pub use tile_front::{TileCandidate, TileFront, run_tile};
#[cfg(not(target_arch = "wasm32"))]
pub use within::{TiledWithin, tiled_member_within, tiled_mesh_within};
// The browser's tiled run (and its native tests) keep each tile's members.
#[cfg(any(test, target_arch = "wasm32"))]
pub(crate) use tile_front::run_tile_keeping;
// The browser checks its tile size input against it.
#[cfg(any(test, target_arch = "wasm32"))]
pub(crate) use plan::MIN_TILE;

pub(crate) use border::TileBorders;
pub(crate) use tile_front::MEMBERS_PER_TILE;

/// Why a tiling step cannot go on.
#[derive(Clone, Debug, PartialEq)]
pub enum TilingError {
    /// The tile size is under `MIN_TILE`.
    TileTooSmall {
        /// The size asked for.
        tile: usize,
        /// The smallest allowed.
        min: usize,
    },
    /// The grid is under 2×2.
    GridTooSmall {
        /// W.
        width: usize,
        /// H.
        height: usize,
    },
    /// A grid (or tile) of another size than the plan's.
    GridMismatch {
        /// (W, H) the plan expects.
        plan: (usize, usize),
        /// (W, H) given.
        grid: (usize, usize),
    },
    /// A tile index beyond the plan.
    NoSuchTile {
        /// The index asked for.
        index: usize,
        /// Tiles in the plan.
        tiles: usize,
    },
    /// A member index beyond the front.
    NoSuchMember {
        /// The index asked for.
        member: usize,
        /// Members there are.
        members: usize,
    },
    /// [`assemble()`] did not get exactly one front per tile.
    WrongTiles {
        /// Tiles in the plan.
        expected: usize,
        /// The tile indices given, sorted.
        given: Vec<usize>,
    },
    /// [`assemble()`] got tiles run in different error measures.
    MixedMeasures {
        /// Tile 0's measure.
        first: crate::measure::ErrorMeasure,
        /// The first tile run in another one.
        index: usize,
        /// Its measure.
        other: crate::measure::ErrorMeasure,
    },
    /// Parameters the algorithm refuses.
    BadParams {
        /// The algorithm.
        algorithm: crate::catalogue::Algorithm,
        /// Why.
        reason: String,
    },
    /// A tile's grid could not be made.
    Grid(String),
    /// The evaluator refused a kept set.
    Evaluate(String),
    /// The thread pool could not start.
    Threads(String),
}

impl std::fmt::Display for TilingError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TileTooSmall { tile, min } => write!(
                f,
                "a tile of {tile} points a side is too small: tiles need at least {min} points a side"
            ),
            Self::GridTooSmall { width, height } => {
                write!(
                    f,
                    "the grid is {width}×{height}; tiling needs at least 2×2 points"
                )
            }
            Self::GridMismatch { plan, grid } => write!(
                f,
                "the grid is {}×{} but the tile plan is for {}×{}",
                grid.0, grid.1, plan.0, plan.1
            ),
            Self::NoSuchTile { index, tiles } => {
                write!(f, "there is no tile {index}: the plan has {tiles} tiles")
            }
            Self::NoSuchMember { member, members } => {
                write!(f, "there is no member {member}: the front has {members}")
            }
            Self::WrongTiles { expected, given } => write!(
                f,
                "assembling needs one front for each of the {expected} tiles, got tiles {given:?}"
            ),
            Self::MixedMeasures {
                first,
                index,
                other,
            } => write!(
                f,
                "tile 0 was run in error measure {first}, tile {index} in {other}"
            ),
            Self::BadParams { algorithm, reason } => {
                write!(f, "bad parameters for {}: {reason}", algorithm.name())
            }
            Self::Grid(e) => write!(f, "cannot cut the tile: {e}"),
            Self::Evaluate(e) => write!(f, "cannot score a tile's mesh: {e}"),
            Self::Threads(e) => write!(f, "cannot start the threads: {e}"),
        }
    }
}

impl std::error::Error for TilingError {}
