//! Parsing off the main thread: `www/worker.js` runs
//! [`parse_surface`](super::bindings::parse_surface) in a Web Worker and posts the height field
//! back as a plain object (z as a transferable `Float64Array`); [`surface_from_js`] rebuilds it
//! on the main thread. So a file of tens of MB never blocks the page for more than the copy of
//! its heights.

use crate::heightfield::{Heightfield, Placement};
use js_sys::{Array, Float64Array, Object, Reflect};
use wasm_bindgen::prelude::*;

fn set(o: &Object, key: &str, value: &JsValue) -> Result<(), JsValue> {
    Reflect::set(o, &key.into(), value).map(|_| ())
}

fn numbers(values: &[f64]) -> JsValue {
    values
        .iter()
        .map(|&v| JsValue::from_f64(v))
        .collect::<Array>()
        .into()
}

/// The plain-object form of `hf`: `{width, height, z, origin, spacing, placement, source,
/// filled}`; `placement` is `{kind, values}` with the placement's vectors flattened.
pub fn surface_to_js(hf: &Heightfield) -> Result<JsValue, JsValue> {
    let o = Object::new();
    set(&o, "width", &JsValue::from_f64(hf.width() as f64))?;
    set(&o, "height", &JsValue::from_f64(hf.height() as f64))?;
    set(&o, "z", &Float64Array::from(hf.z()).into())?;
    set(&o, "origin", &numbers(&hf.origin()))?;
    set(&o, "spacing", &numbers(&hf.spacing()))?;
    let (kind, values): (&str, Vec<f64>) = match hf.placement() {
        Placement::Grid => ("grid", vec![]),
        Placement::Planar { origin, u, v, n } => (
            "planar",
            [origin, u, v, n]
                .iter()
                .flat_map(|a| a.iter().copied())
                .collect(),
        ),
        Placement::Cylindrical {
            origin,
            axis,
            reference,
        } => (
            "cylindrical",
            [origin, axis, reference]
                .iter()
                .flat_map(|a| a.iter().copied())
                .collect(),
        ),
    };
    let p = Object::new();
    set(&p, "kind", &kind.into())?;
    set(&p, "values", &numbers(&values))?;
    set(&o, "placement", &p)?;
    set(&o, "source", &hf.source().into())?;
    set(&o, "filled", &JsValue::from_f64(hf.filled() as f64))?;
    Ok(o.into())
}

fn get(o: &JsValue, key: &str) -> Result<JsValue, String> {
    Reflect::get(o, &key.into()).map_err(|_| format!("parsed surface lacks {key}"))
}

fn number(o: &JsValue, key: &str) -> Result<f64, String> {
    get(o, key)?
        .as_f64()
        .ok_or_else(|| format!("parsed surface: {key} is not a number"))
}

fn vector<const N: usize>(values: &[f64], at: usize) -> Result<[f64; N], String> {
    values
        .get(at..at + N)
        .and_then(|s| s.try_into().ok())
        .ok_or_else(|| "parsed surface: placement has too few values".to_string())
}

fn number_list(o: &JsValue, key: &str) -> Result<Vec<f64>, String> {
    let a: Array = get(o, key)?
        .dyn_into()
        .map_err(|_| format!("parsed surface: {key} is not a list"))?;
    a.iter()
        .map(|v| {
            v.as_f64()
                .ok_or_else(|| format!("parsed surface: {key} holds a non-number"))
        })
        .collect()
}

/// Rebuilds a height field from [`surface_to_js`]'s form, validating it like any input.
pub fn surface_from_js(o: &JsValue) -> Result<Heightfield, String> {
    let width = number(o, "width")? as usize;
    let height = number(o, "height")? as usize;
    let z: Float64Array = get(o, "z")?
        .dyn_into()
        .map_err(|_| "parsed surface: z is not a Float64Array")?;
    let origin = number_list(o, "origin")?;
    let spacing = number_list(o, "spacing")?;
    let p = get(o, "placement")?;
    let kind = get(&p, "kind")?.as_string().unwrap_or_default();
    let values = number_list(&p, "values")?;
    let placement = match kind.as_str() {
        "grid" => Placement::Grid,
        "planar" => Placement::Planar {
            origin: vector(&values, 0)?,
            u: vector(&values, 3)?,
            v: vector(&values, 6)?,
            n: vector(&values, 9)?,
        },
        "cylindrical" => Placement::Cylindrical {
            origin: vector(&values, 0)?,
            axis: vector(&values, 3)?,
            reference: vector(&values, 6)?,
        },
        other => return Err(format!("parsed surface: unknown placement {other}")),
    };
    let source = get(o, "source")?.as_string().unwrap_or_default();
    let filled = number(o, "filled")? as usize;
    let hf = Heightfield::new(width, height, z.to_vec())
        .map_err(|e| e.to_string())?
        .with_geometry(vector(&origin, 0)?, vector(&spacing, 0)?)
        .map_err(|e| e.to_string())?
        .with_placement(placement)
        .with_source(source)
        .with_filled(filled);
    // A share link of a resampled mesh records how it was gridded (see `share::ImportChoice`).
    let resampled = get(o, "resampled")?.as_bool().unwrap_or(false);
    Ok(if resampled { hf.with_resampled() } else { hf })
}
