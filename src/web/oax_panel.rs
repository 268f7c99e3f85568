//! The teaching view's panel on the last orthogonal-array crossover: the array (rows ×
//! factors, A = the block from parent A, B = from parent B), each row's child with its fitness
//! and objectives, the factor effects, the best-levels child, and a thumbnail of every mesh
//! (the parents' and the children's) that shows it in the main view when clicked.

use super::dom::{self, by_id};
use super::plot::format_value;
use crate::evaluator::Evaluator;
use crate::evaluator::exact::predicates::Lattice;
use crate::evolution::oax::{OaxChild, OaxRecord};
use crate::front::Solution;
use crate::heightfield::Heightfield;
use std::fmt::Write;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

/// Thumbnail side in CSS pixels.
const THUMB: u32 = 48;

/// Every mesh the panel shows, in thumbnail order: parent A, parent B, the rows, best-levels.
pub fn meshes(record: &OaxRecord) -> Vec<Solution> {
    let parents = record.parents.iter().map(|(g, o)| (g, *o));
    let children = record
        .rows
        .iter()
        .chain(std::iter::once(&record.best_levels))
        .map(|c| (&c.genes, c.objectives));
    parents
        .chain(children)
        .map(|(genes, o)| Solution {
            score: o,
            kept: genes.indices(),
        })
        .collect()
}

fn levels(child: &OaxChild) -> String {
    child
        .levels
        .iter()
        .map(|&l| {
            format!(
                "<td class=\"lv{l}\">{}</td>",
                if l == 0 { 'A' } else { 'B' }
            )
        })
        .collect()
}

/// The panel's HTML for `record` (thumbnails are `<canvas data-mesh="k">`, drawn afterwards).
pub fn html(record: &OaxRecord) -> String {
    let factors = record.blocks.len();
    let m = record.array.rows();
    let mut h = String::new();
    let _ = write!(
        h,
        "<p class=\"small\">Array L<sub>{m}</sub>(2<sup>{}</sup>), {factors} factors (rectangular \
         blocks of the grid); scalar fitness F = w·E/E₀ + (1 − w)·T/T₀ with w = {:.3} (smaller \
         is better). ★ marks the two children kept.</p>",
        m - 1,
        record.weight
    );
    h.push_str(
        "<table class=\"oax\"><thead><tr><th>mesh</th><th></th><th>F</th><th>E</th><th>T</th>",
    );
    for f in 0..factors {
        let _ = write!(h, "<th>f{}</th>", f + 1);
    }
    h.push_str("</tr></thead><tbody>");
    for (k, name) in ["parent A", "parent B"].iter().enumerate() {
        let o = record.parents[k].1;
        let level = if k == 0 { 'A' } else { 'B' };
        let _ = write!(
            h,
            "<tr class=\"parent\"><td><canvas data-mesh=\"{k}\" title=\"show {name} in the 3-D view\"></canvas></td><th>{name}</th><td></td><td>{}</td><td class=\"t\">{}</td>{}</tr>",
            format_value(o.e_sum),
            o.t,
            format!("<td class=\"lv{k}\">{level}</td>").repeat(factors),
        );
    }
    let best = record.rows.len();
    for (i, child) in record
        .rows
        .iter()
        .chain(std::iter::once(&record.best_levels))
        .enumerate()
    {
        let star = if record.chosen.contains(&i) {
            " ★"
        } else {
            ""
        };
        let name = if i == best {
            "best levels".to_string()
        } else {
            format!("row {}", i + 1)
        };
        let class = if i == best { "best" } else { "row" };
        let _ = write!(
            h,
            "<tr class=\"{class}\"><td><canvas data-mesh=\"{}\" title=\"show {name} in the 3-D view\"></canvas></td><th>{name}{star}</th><td>{:.4}</td><td>{}</td><td class=\"t\">{}</td>{}</tr>",
            i + 2,
            child.fitness,
            format_value(child.objectives.e_sum),
            child.objectives.t,
            levels(child),
        );
    }
    for (l, label) in ["Σ F at A", "Σ F at B"].iter().enumerate() {
        let _ = write!(
            h,
            "<tr class=\"effects\"><td></td><th>{label}</th><td></td><td></td><td></td>"
        );
        for e in &record.effects {
            // The best level minimises F; ties go to A, as in the factor analysis.
            let best = usize::from(e[1] < e[0]);
            let better = l == best;
            let _ = write!(
                h,
                "<td{}>{:.2}</td>",
                if better { " class=\"chosen\"" } else { "" },
                e[l]
            );
        }
        h.push_str("</tr>");
    }
    h.push_str("</tbody></table>");
    h
}

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
pub fn show(record: Option<&OaxRecord>, hf: &Arc<Heightfield>) {
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
