//! The import dialog's preview: a parsed grid drawn as a shaded grey image.

use super::transfer::surface_from_js;
use wasm_bindgen::prelude::*;
use wasm_bindgen::{Clamped, JsCast};
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement, ImageData};

/// Grey levels of a `width` × `height` grid: height mapped to 40..=255, lightened or darkened by
/// the slope towards the upper left so relief shows. Returns RGBA bytes, row-major.
pub fn preview_pixels(width: usize, height: usize, z: &[f64]) -> Vec<u8> {
    let (lo, hi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = if hi > lo { hi - lo } else { 1.0 };
    let mut out = Vec::with_capacity(width * height * 4);
    for y in 0..height {
        for x in 0..width {
            let v = z[y * width + x];
            let left = z[y * width + x.saturating_sub(1)];
            let up = z[y.saturating_sub(1) * width + x];
            let shade = ((v - left) + (v - up)) / span * 4.0 * 255.0;
            let g = (40.0 + (v - lo) / span * 215.0 + shade).clamp(0.0, 255.0) as u8;
            out.extend_from_slice(&[g, g, g, 255]);
        }
    }
    out
}

/// Draws a parsed surface (the Worker's plain-object form) on canvas `canvas_id`, one pixel per
/// grid point, scaled to the canvas by CSS.
#[wasm_bindgen(js_name = drawPreview)]
pub fn draw_preview(canvas_id: &str, surface: JsValue) -> Result<(), JsError> {
    let hf = surface_from_js(&surface).map_err(|e| JsError::new(&e))?;
    let canvas: HtmlCanvasElement = super::dom::by_id(canvas_id).map_err(|e| JsError::new(&e))?;
    canvas.set_width(hf.width() as u32);
    canvas.set_height(hf.height() as u32);
    let ctx: CanvasRenderingContext2d = canvas
        .get_context("2d")
        .ok()
        .flatten()
        .ok_or_else(|| JsError::new("no 2-D canvas"))?
        .unchecked_into();
    let pixels = preview_pixels(hf.width(), hf.height(), hf.z());
    let image = ImageData::new_with_u8_clamped_array_and_sh(
        Clamped(&pixels),
        hf.width() as u32,
        hf.height() as u32,
    )
    .map_err(|_| JsError::new("cannot build the preview image"))?;
    ctx.put_image_data(&image, 0.0, 0.0)
        .map_err(|_| JsError::new("cannot draw the preview"))?;
    Ok(())
}
