//! Parsing off the main thread: `www/worker.js` runs
//! [`parse_surface`](super::bindings::parse_surface) in a Web Worker and posts the height field
//! back as a plain object (z as a transferable `Float64Array`); [`surface_from_js`] rebuilds it
//! on the main thread. So a file of tens of MB never blocks the page for more than the copy of
//! its heights. The object is [`SurfaceParts`] field by field, so nothing the Worker parsed
//! (the GeoTIFF georeferencing included) is lost on the way.

use crate::app::handoff::SurfaceParts;
use crate::heightfield::{Georeference, Heightfield};
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

fn optional_numbers(values: Option<&[f64]>) -> JsValue {
    values.map_or(JsValue::NULL, numbers)
}

/// The georeferencing as `{pixelScale, tiepoint, pixelIsPoint, nodata, epsg}` (absent tags are null).
fn georeference_to_js(geo: &Georeference) -> Result<JsValue, JsValue> {
    let o = Object::new();
    set(
        &o,
        "pixelScale",
        &optional_numbers(geo.pixel_scale.as_ref().map(|a| &a[..])),
    )?;
    set(
        &o,
        "tiepoint",
        &optional_numbers(geo.tiepoint.as_ref().map(|a| &a[..])),
    )?;
    set(&o, "pixelIsPoint", &geo.pixel_is_point.into())?;
    set(
        &o,
        "nodata",
        &geo.nodata.as_deref().map_or(JsValue::NULL, JsValue::from),
    )?;
    set(
        &o,
        "epsg",
        &geo.epsg
            .map_or(JsValue::NULL, |c| JsValue::from(f64::from(c))),
    )?;
    Ok(o.into())
}

/// The plain-object form of `hf`: `{width, height, z, origin, spacing, placement, source,
/// filled, resampled, georeference}`; `placement` is `{kind, values}` with the placement's
/// vectors flattened, `georeference` null for a grid not read from a GeoTIFF.
pub(super) fn surface_to_js(hf: &Heightfield) -> Result<JsValue, JsValue> {
    let parts = SurfaceParts::of(hf);
    let o = Object::new();
    set(&o, "width", &JsValue::from_f64(parts.width as f64))?;
    set(&o, "height", &JsValue::from_f64(parts.height as f64))?;
    set(&o, "z", &Float64Array::from(&parts.z[..]).into())?;
    set(&o, "origin", &numbers(&parts.origin))?;
    set(&o, "spacing", &numbers(&parts.spacing))?;
    let p = Object::new();
    set(&p, "kind", &parts.placement_kind.as_str().into())?;
    set(&p, "values", &numbers(&parts.placement_values))?;
    set(&o, "placement", &p)?;
    set(&o, "source", &parts.source.as_str().into())?;
    set(&o, "filled", &JsValue::from_f64(parts.filled as f64))?;
    set(&o, "resampled", &parts.resampled.into())?;
    let geo = match &parts.georeference {
        Some(geo) => georeference_to_js(geo)?,
        None => JsValue::NULL,
    };
    set(&o, "georeference", &geo)?;
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

fn array<const N: usize>(values: &[f64], key: &str) -> Result<[f64; N], String> {
    values
        .try_into()
        .map_err(|_| format!("parsed surface: {key} does not hold {N} numbers"))
}

/// `o[key]` as N numbers; `None` when it is null or absent.
fn optional_array<const N: usize>(o: &JsValue, key: &str) -> Result<Option<[f64; N]>, String> {
    if get(o, key)?.is_null_or_undefined() {
        return Ok(None);
    }
    array(&number_list(o, key)?, key).map(Some)
}

fn georeference_from_js(o: &JsValue) -> Result<Option<Georeference>, String> {
    let geo = get(o, "georeference")?;
    if geo.is_null_or_undefined() {
        return Ok(None);
    }
    Ok(Some(Georeference {
        pixel_scale: optional_array(&geo, "pixelScale")?,
        tiepoint: optional_array(&geo, "tiepoint")?,
        pixel_is_point: get(&geo, "pixelIsPoint")?.as_bool().unwrap_or(false),
        nodata: get(&geo, "nodata")?.as_string(),
        epsg: get(&geo, "epsg")?
            .as_f64()
            .filter(|c| c.fract() == 0.0 && (1.0..=65535.0).contains(c))
            .map(|c| c as u16),
    }))
}

/// Rebuilds a height field from [`surface_to_js`]'s form, validating it like any input.
pub(super) fn surface_from_js(o: &JsValue) -> Result<Heightfield, String> {
    let z: Float64Array = get(o, "z")?
        .dyn_into()
        .map_err(|_| "parsed surface: z is not a Float64Array")?;
    let p = get(o, "placement")?;
    SurfaceParts {
        width: number(o, "width")? as usize,
        height: number(o, "height")? as usize,
        z: z.to_vec(),
        origin: array(&number_list(o, "origin")?, "origin")?,
        spacing: array(&number_list(o, "spacing")?, "spacing")?,
        placement_kind: get(&p, "kind")?.as_string().unwrap_or_default(),
        placement_values: number_list(&p, "values")?,
        source: get(o, "source")?.as_string().unwrap_or_default(),
        filled: number(o, "filled")? as usize,
        // A share link of a resampled mesh records how it was gridded (see `share::ImportChoice`).
        resampled: get(o, "resampled")?.as_bool().unwrap_or(false),
        georeference: georeference_from_js(o)?,
    }
    .into_heightfield()
}
