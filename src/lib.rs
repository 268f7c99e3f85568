//! # ParetoMesh
//!
//! Simplifies an open surface given as a height field by finding the whole Pareto front of
//! (error, triangle count) meshes, after the source paper's NSGA-II with orthogonal-array
//! crossover and its baselines.
//!
//! - [`heightfield`]: the height field z = f(x, y) on a W×H grid and its import (raw f32, PNG,
//!   GeoTIFF, PLY, OBJ, STL).
//! - [`export`]: writing meshes for other 3-D tools (binary glTF).
//! - [`evaluator`]: the ruler: Delaunay triangulation of a kept set of grid points and the exact
//!   error E = Σ|z − z̃| over every grid point, counted once.
//! - [`front`]: solutions and the non-dominated front of (E, T).
//! - [`optimizer`]: the steppable interface every algorithm implements.
//! - [`evolution`]: NSGA-II, orthogonal-array crossover, the weighted-sum GA.
//! - [`baselines`]: greedy insertion and edge decimation.
//! - [`run_file`]: front.json, the self-contained result of a run.
//! - [`metrics`]: hypervolume, epsilon, coverage, Wilcoxon rank-sum, trade-off picks.
//! - [`experiment`]: the paper's experiment: protocol, results.json, report tables, figure.
//! - [`export`]: mesh writers (PLY, OBJ, STL) and the front as CSV, for the CLI and the app.
//! - [`tiling`]: large grids in crack-free tiles, run in parallel, one whole-grid front.
//! - [`app`]: the browser app's logic without the DOM (state, share links, plot layout, ...).
//! - `web` (wasm32 only): the browser layer: bindings, page, events, views and GPU.

pub mod app;
pub mod baselines;
pub mod evaluator;
pub mod evolution;
pub mod experiment;
pub mod export;
pub mod front;
pub mod heightfield;
pub mod import;
pub mod metrics;
pub mod optimizer;
pub mod run_file;
pub mod tiling;

#[cfg(target_arch = "wasm32")]
pub mod web;
