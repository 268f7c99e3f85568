//! The browser app's logic, free of the DOM so that it builds and is tested natively; the
//! browser layer (`web`, wasm32 only) puts it on the page.
//!
//! - [`state`]: the app state and time-budgeted stepping of the chosen algorithm.
//! - [`algorithms`]: the algorithm menu, parameters with the paper's defaults, the builder.
//! - [`compare`]: compare mode: every method side by side and their indicator table;
//!   [`compare_html`] renders that table.
//! - [`share`]: the share-link codec and its validation; [`examples`] are curated links.
//! - [`teaching`]: the teaching view's phases and scenes; [`oax_panel`] its crossover panel.
//! - [`plot`]: the E–T plot's layout and hit-testing.
//! - [`camera`] and [`geometry`]: the 3-D view's orbit camera and vertex data.
//! - [`loader`]: built-in surfaces and file parsing; [`preview`] the import dialog's image;
//!   [`handoff`] the parsed surface as plain parts, for the import Worker's hand-off.
//! - [`pool`]: a run done by a pool of Web Workers, as the page sees it; [`tiled_run`] its
//!   tiles, their fronts and the whole-grid front assembled from them; [`mesh_builds`] a
//!   member's mesh built in a worker.
//! - [`glb_export`]: the shown mesh as `.glb`; [`pyramid_export`] the front as a 3D Tiles
//!   pyramid in a `.zip`.

pub(crate) mod algorithms;
pub(crate) mod camera;
pub(crate) mod compare;
pub(crate) mod compare_html;
pub(crate) mod examples;
pub(crate) mod geometry;
pub(crate) mod glb_export;
pub(crate) mod handoff;
pub(crate) mod loader;
pub(crate) mod mesh_builds;
pub(crate) mod oax_panel;
pub(crate) mod plot;
pub(crate) mod pool;
pub(crate) mod preview;
pub(crate) mod pyramid_export;
pub mod share;
pub(crate) mod state;
pub(crate) mod teaching;
pub(crate) mod tiled_run;

#[cfg(test)]
mod tests;
