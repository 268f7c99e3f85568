//! The teaching view's panel on the last orthogonal-array crossover on the page: its HTML
//! (from [`crate::app::oax_panel`]) and a thumbnail of every mesh, which shows that mesh in the
//! main view when clicked.

use super::dom::{self, by_id};
use crate::app::oax_panel::{html, meshes};
use crate::evaluator::Evaluator;
use crate::evaluator::exact::predicates::Lattice;
use crate::evolution::oax::OaxRecord;
use crate::heightfield::Heightfield;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

/// Thumbnail side in CSS pixels.
const THUMB: u32 = 48;

/// Draws the mesh of `kept` on `hf` into `canvas`: its triangles' edges in the grid's (x, y)
/// plane, with the kept points.
fn draw_thumbnail(canvas: &HtmlCanvasElement, hf: &Arc<Heightfield>, kept: &[u32]) {
    let dpr = web_sys::window().map_or(1.0, |w| w.device_pixel_ratio());
    let side = (THUMB as f64 * dpr).round() as u32;
    canvas.set_width(side);
    canvas.set_height(side);
    let Ok(Some(ctx)) = canvas.get_context("2d") else {
        return;
    };
    let ctx: CanvasRenderingContext2d = ctx.unchecked_into();
    ctx.set_fill_style_str("#fff");
    ctx.fill_rect(0.0, 0.0, side as f64, side as f64);
    let Ok(evaluation) = Evaluator::new(hf.clone()).evaluate(kept) else {
        return;
    };
    let (w, h) = (hf.width() as f64 - 1.0, hf.height() as f64 - 1.0);
    let scale = (side as f64 - 4.0) / w.max(h);
    let lattice = Lattice::new(hf.width());
    let at = |i: u32| {
        let p = lattice.point(i);
        (2.0 + p[0] as f64 * scale, 2.0 + p[1] as f64 * scale)
    };
    ctx.set_stroke_style_str("#345");
    ctx.set_line_width(0.6 * dpr);
    ctx.begin_path();
    for tri in &evaluation.triangles {
        let (x0, y0) = at(tri[0]);
        ctx.move_to(x0, y0);
        for &v in &tri[1..] {
            let (x, y) = at(v);
            ctx.line_to(x, y);
        }
        ctx.close_path();
    }
    ctx.stroke();
}

/// Fills the `#oax` panel with `record` on `hf`, or says there is none yet.
pub(super) fn show(record: Option<&OaxRecord>, hf: &Arc<Heightfield>) {
    let Ok(panel) = by_id::<web_sys::Element>("oax") else {
        return;
    };
    let Some(record) = record else {
        panel.set_inner_html(
            "<p class=\"small\">No orthogonal-array crossover yet: run a generation of NSGA-II \
             with OAX.</p>",
        );
        return;
    };
    panel.set_inner_html(&html(record));
    let meshes = meshes(record);
    if let Ok(list) = panel.query_selector_all("canvas[data-mesh]") {
        for i in 0..list.length() {
            let Some(canvas) = list
                .item(i)
                .and_then(|n| n.dyn_into::<HtmlCanvasElement>().ok())
            else {
                continue;
            };
            let k: usize = canvas
                .get_attribute("data-mesh")
                .and_then(|v| v.parse().ok())
                .unwrap_or(usize::MAX);
            if let Some(m) = meshes.get(k) {
                draw_thumbnail(&canvas, hf, &m.kept);
            }
        }
    }
    dom::set_text(
        "oax-summary",
        &format!(
            "{} rows, {} evaluations spent",
            record.rows.len() + 1,
            record.evaluations()
        ),
    );
}
