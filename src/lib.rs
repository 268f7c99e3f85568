//! # ParetoMesh
//!
//! Simplifies an open surface given as a height field by finding the whole Pareto front of
//! (error, triangle count) meshes, after the source paper's NSGA-II with orthogonal-array
//! crossover and its baselines.
//!
//! - [`heightfield`]: the height field z = f(x, y) on a W×H grid, its spacing, origin and
//!   georeference.
//! - [`import`]: reading a file into a height field (raw f32, PNG, GeoTIFF, PLY, OBJ, STL).
//! - [`evaluator`]: the ruler: Delaunay triangulation of a kept set of grid points and the exact
//!   error E = Σ|z − z̃| over every grid point, counted once.
//! - [`front`]: solutions and the non-dominated front of (E, T).
//! - [`measure`]: the error measure (E_sum, RMS or E_max) a front minimises beside T.
//! - [`optimizer`]: the steppable interface every algorithm implements.
//! - [`evolution`]: NSGA-II, orthogonal-array crossover, the weighted-sum GA, the memetic
//!   method.
//! - [`baselines`]: greedy insertion and edge decimation.
//! - [`catalogue`]: every method with its names, budget kind, the parameters it reads and how
//!   it is built; the CLI, the experiment and the app take their methods from it.
//! - [`front_file`]: front.json, the self-contained result of a run; [`kept_codec`] packs its
//!   kept sets.
//! - [`pick`]: choosing one member of a front (index, trade-off, knee, limits on T or error).
//! - [`metrics`]: hypervolume, epsilon, coverage, Wilcoxon rank-sum, trade-off picks.
//! - [`experiment`]: the paper's experiment: protocol, results.json, report tables, figure.
//! - [`export`]: mesh writers (PLY, OBJ, STL, binary glTF, 3MF), printable solids and the front
//!   as CSV, for the CLI and the app.
//! - [`refine`]: a member grown to an exact triangle budget by exact worst-point insertions.
//! - [`tiling`]: large grids in crack-free tiles, run in parallel, one whole-grid front.
//! - [`pyramid`]: a 3D Tiles pyramid of a front's members, placed on the globe when georeferenced.
//! - `terrain` (native only): terrain tiles of a DEM for web globes, quantized-mesh-1.0 or 3D
//!   Tiles terrain (`paretomesh tiles`).
//! - `web` (wasm32 only): the browser layer: bindings, page, events, views and GPU, on the
//!   app's logic (state, share links, plot layout, ...), which is the crate's own.
//!
//! Modules with several files keep them private (or `pub(crate)`) and re-export their API at
//! the top; `evolution` also keeps `chromosome`, `oax`, `trace` and `memetic`
//! public, and `experiment` its `external`. `tests/public-api.txt` lists the whole public API;
//! `scripts/public-api.sh` checks it.

pub mod baselines;
pub mod catalogue;
pub mod evaluator;
pub mod evolution;
pub mod experiment;
pub mod export;
pub mod front;
pub mod front_file;
pub mod heightfield;
pub mod import;
pub mod kept_codec;
pub(crate) mod lazy_queue;
pub mod measure;
pub mod metrics;
pub mod optimizer;
pub mod pick;
pub mod pyramid;
pub mod refine;
#[cfg(not(target_arch = "wasm32"))]
pub mod terrain;
pub mod tiling;
pub(crate) mod xml;

// The browser app's logic without the DOM: only `web` (wasm32) and the crate's tests use it, so
// a native build leaves its page-only parts (and their re-exports) unused.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code, unused_imports))]
pub(crate) mod app;

#[cfg(target_arch = "wasm32")]
pub mod web;

/// The app's share-link codec, for the fuzz harness (`fuzz/`) and its replay on stable
/// (`tests/fuzz_corpus.rs`); not part of the library's API.
#[cfg(feature = "test-support")]
#[doc(hidden)]
pub use app::share;
