//! The browser layer (wasm32 only): the app over the core. `index.html` and `www/main.js` boot
//! it; the JS only wires the file drop and the `requestAnimationFrame` loop, everything else is
//! here.
//!
//! - [`app`]: app state and time-budgeted stepping (pure, tested).
//! - [`algorithms`]: the algorithm menu, parameters with the paper's defaults, the builder.
//! - [`plot`]: the E–T plot and its hit-testing.
//! - [`compare`]: compare mode: the four methods side by side and their indicator table.
//! - [`render`]: the 3-D view through wgpu.
//! - [`export`]: PLY / OBJ / STL / CSV exports.
//! - [`share`]: the share-link codec and its validation.
//! - [`dom`]: the page's controls.
//! - [`ui`]: the glue: events, the frame, the panic hook.

pub mod algorithms;
pub mod app;
pub mod compare;
pub mod dom;
pub mod examples;
pub mod export;
pub mod loader;
pub mod oax_panel;
pub mod plot;
pub mod preview;
pub mod render;
pub mod share;
pub mod share_view;
pub mod teaching;
pub mod teaching_view;
pub mod transfer;
pub mod ui;

use crate::{evaluator::Evaluator, heightfield::raw};
use wasm_bindgen::prelude::*;

pub use ui::WebApp;

/// Loads a raw f32 grid with its JSON sidecar, scores the kept indices, and returns the
/// evaluation as a JS object `{E_sum, E_max, rms, T, triangles}`.
#[wasm_bindgen(js_name = evaluateRaw)]
pub fn evaluate_raw(grid: &[u8], sidecar: &[u8], kept: &[u32]) -> Result<JsValue, JsError> {
    let hf = raw::parse(grid, sidecar, "upload").map_err(|e| JsError::new(&e.to_string()))?;
    let evaluation = Evaluator::new(std::sync::Arc::new(hf))
        .evaluate(kept)
        .map_err(|e| JsError::new(&e.to_string()))?;
    // JSON-compatible: plain objects (not `Map`s) for the flattened score.
    let serializer = serde_wasm_bindgen::Serializer::json_compatible();
    serde::Serialize::serialize(&evaluation, &serializer).map_err(|e| JsError::new(&e.to_string()))
}
