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

pub mod algorithms;
pub mod camera;
pub mod compare;
pub mod compare_html;
pub mod examples;
pub mod geometry;
pub mod glb_export;
pub mod handoff;
pub mod loader;
pub mod mesh_builds;
pub mod oax_panel;
pub mod plot;
pub mod pool;
pub mod preview;
pub mod pyramid_export;
pub mod share;
pub mod state;
pub mod teaching;
pub mod tiled_run;

#[cfg(test)]
mod tests;
