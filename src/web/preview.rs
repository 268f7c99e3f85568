//! The import dialog's preview: a parsed grid drawn as a shaded grey image.

use super::dom::by_id;
use crate::app::preview::preview_pixels;
use crate::heightfield::Heightfield;
use wasm_bindgen::{Clamped, JsCast};
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement, ImageData};

/// Draws `hf` on canvas `canvas_id`, one pixel per grid point, scaled to the canvas by CSS.
pub(super) fn draw(canvas_id: &str, hf: &Heightfield) -> Result<(), String> {
    let canvas: HtmlCanvasElement = by_id(canvas_id)?;
    canvas.set_width(hf.width() as u32);
    canvas.set_height(hf.height() as u32);
    let ctx: CanvasRenderingContext2d = canvas
        .get_context("2d")
        .ok()
        .flatten()
        .ok_or("no 2-D canvas")?
        .unchecked_into();
    let pixels = preview_pixels(hf.width(), hf.height(), hf.z());
    let image = ImageData::new_with_u8_clamped_array_and_sh(
        Clamped(&pixels),
        hf.width() as u32,
        hf.height() as u32,
    )
    .map_err(|_| "cannot build the preview image")?;
    ctx.put_image_data(&image, 0.0, 0.0)
        .map_err(|_| "cannot draw the preview")?;
    Ok(())
}
