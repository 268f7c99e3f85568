//! The browser layer (wasm32 only): a thin shell over the core.

use crate::{evaluator::Evaluator, heightfield::raw};
use wasm_bindgen::prelude::*;

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
