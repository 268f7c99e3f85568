//! Paints the E–T plot on a canvas: axes with labels and units, the population coloured by
//! non-domination rank, the archive front, the selection, hover read-outs, and the marks of the
//! teaching and comparison scenes. Layout and hit-testing are in [`crate::app::plot`].

use crate::app::plot::{
    E_TITLE_LEFT, EAxis, Layout, Mark, PlotPoint, Scene, Shape, TICK_FONT_PX, TICK_GAP,
    format_value, rank_colour, ticks,
};
use web_sys::CanvasRenderingContext2d;

/// Draws `scene` on `ctx` (already scaled to CSS pixels) with `layout`.
pub(super) fn draw(ctx: &CanvasRenderingContext2d, layout: &Layout, scene: &Scene) {
    let (w, h) = (layout.width, layout.height);
    let (l, t, r, b) = layout.area();
    ctx.set_fill_style_str("#ffffff");
    ctx.fill_rect(0.0, 0.0, w, h);
    axes(ctx, layout, scene.z_unit, scene.e_axis);
    // Clip the data to the plotting area.
    ctx.save();
    ctx.begin_path();
    ctx.rect(l, t, r - l, b - t);
    ctx.clip();
    data(ctx, layout, scene);
    ctx.restore();
    // Hover read-out.
    if let Some(i) = scene.hovered
        && let Some(p) = scene.front.get(i)
    {
        let text = scene
            .labels
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("T = {}, E = {}", p.t, format_value(p.e)));
        readout(ctx, layout, *p, &text);
    }
}

/// The grid, the ticks with their labels, the frame and the axis titles (E in `z_unit`). The
/// layout's left margin leaves the E title its own band beside the widest tick label.
fn axes(ctx: &CanvasRenderingContext2d, layout: &Layout, z_unit: &str, e_axis: EAxis) {
    let h = layout.height;
    let (l, t, r, b) = layout.area();
    ctx.set_font(&format!("{TICK_FONT_PX}px system-ui, sans-serif"));
    ctx.set_line_width(1.0);
    ctx.set_stroke_style_str("#e6e6e6");
    ctx.set_fill_style_str("#444");
    ctx.set_text_align("center");
    ctx.set_text_baseline("top");
    for v in ticks(layout.t_range.0, layout.t_range.1, 6) {
        let (x, _) = layout.to_pixel(PlotPoint {
            t: v,
            e: layout.e_range.0,
        });
        line(ctx, x, t, x, b);
        let _ = ctx.fill_text(&format_value(v), x, b + 4.0);
    }
    ctx.set_text_align("right");
    ctx.set_text_baseline("middle");
    for v in layout.e_ticks() {
        let (_, y) = layout.to_pixel(PlotPoint {
            t: layout.t_range.0,
            e: v,
        });
        line(ctx, l, y, r, y);
        let _ = ctx.fill_text(&format_value(v), l - TICK_GAP, y);
    }
    ctx.set_stroke_style_str("#555");
    ctx.stroke_rect(l, t, r - l, b - t);
    // Axis titles.
    ctx.set_text_align("center");
    ctx.set_text_baseline("bottom");
    let _ = ctx.fill_text("T (triangles)", (l + r) / 2.0, h - 2.0);
    ctx.save();
    // Rotated a quarter turn, the text hangs from its top line towards +x: it fills the band
    // from E_TITLE_LEFT one line wide.
    let _ = ctx.translate(E_TITLE_LEFT, (t + b) / 2.0);
    let _ = ctx.rotate(-std::f64::consts::FRAC_PI_2);
    ctx.set_text_baseline("top");
    let _ = ctx.fill_text(&e_axis.title(z_unit, layout.log_e), 0.0, 0.0);
    ctx.restore();
}

/// The population coloured by rank, the archive front, and the hovered and selected members.
fn data(ctx: &CanvasRenderingContext2d, layout: &Layout, scene: &Scene) {
    for (p, rank) in scene.population {
        let (x, y) = layout.to_pixel(*p);
        ctx.set_fill_style_str(rank_colour(*rank));
        ctx.set_global_alpha(0.55);
        ctx.fill_rect(x - 2.0, y - 2.0, 4.0, 4.0);
    }
    ctx.set_global_alpha(1.0);
    // The archive front as a staircase (the region it dominates) and dots; on the E_max axis
    // the front (non-dominated in E_sum) dominates nothing, so it is dots alone.
    if !scene.front.is_empty() && scene.e_axis != EAxis::Max {
        ctx.set_stroke_style_str("#d62728");
        ctx.set_line_width(1.5);
        ctx.begin_path();
        for (i, p) in scene.front.iter().enumerate() {
            let (x, y) = layout.to_pixel(*p);
            if i == 0 {
                ctx.move_to(x, y);
            } else {
                let (_, prev_y) = layout.to_pixel(scene.front[i - 1]);
                ctx.line_to(x, prev_y);
                ctx.line_to(x, y);
            }
        }
        ctx.stroke();
    }
    ctx.set_fill_style_str("#d62728");
    for p in scene.front {
        let (x, y) = layout.to_pixel(*p);
        ctx.begin_path();
        let _ = ctx.arc(x, y, 3.0, 0.0, std::f64::consts::TAU);
        ctx.fill();
    }
    for (index, colour, radius) in [
        (scene.hovered, "#ff9900", 6.0),
        (scene.selected, "#000000", 7.0),
    ] {
        if let Some(p) = index.and_then(|i| scene.front.get(i)) {
            let (x, y) = layout.to_pixel(*p);
            ctx.set_stroke_style_str(colour);
            ctx.set_line_width(2.0);
            ctx.begin_path();
            let _ = ctx.arc(x, y, radius, 0.0, std::f64::consts::TAU);
            ctx.stroke();
        }
    }
}

/// Draws `text` in a boxed read-out next to data point `p`, kept inside the canvas.
pub(super) fn readout(ctx: &CanvasRenderingContext2d, layout: &Layout, p: PlotPoint, text: &str) {
    let (x, y) = layout.to_pixel(p);
    ctx.set_font("12px system-ui, sans-serif");
    let width = ctx.measure_text(text).map(|m| m.width()).unwrap_or(160.0) + 10.0;
    let bx = (x + 8.0).min(layout.width - width - 2.0).max(2.0);
    let by = (y - 24.0).max(2.0);
    ctx.set_fill_style_str("rgba(255,255,255,0.92)");
    ctx.fill_rect(bx, by, width, 18.0);
    ctx.set_stroke_style_str("#888");
    ctx.set_line_width(1.0);
    ctx.stroke_rect(bx, by, width, 18.0);
    ctx.set_fill_style_str("#000");
    ctx.set_text_align("left");
    ctx.set_text_baseline("middle");
    let _ = ctx.fill_text(text, bx + 5.0, by + 9.0);
}

fn line(ctx: &CanvasRenderingContext2d, x0: f64, y0: f64, x1: f64, y1: f64) {
    ctx.begin_path();
    ctx.move_to(x0, y0);
    ctx.line_to(x1, y1);
    ctx.stroke();
}

/// Draws `marks` over a plot already drawn by [`draw`] (with the same `layout`), a legend in
/// the top-right corner, and a ring on the `hovered` mark.
pub(super) fn draw_marks(
    ctx: &CanvasRenderingContext2d,
    layout: &Layout,
    marks: &[Mark],
    legend: &[(String, &'static str)],
    hovered: Option<usize>,
) {
    let (l, t, r, b) = layout.area();
    ctx.save();
    ctx.begin_path();
    ctx.rect(l, t, r - l, b - t);
    ctx.clip();
    for m in marks {
        let (x, y) = layout.to_pixel(m.point);
        let s = m.radius;
        ctx.begin_path();
        match m.shape {
            Shape::Circle => {
                let _ = ctx.arc(x, y, s, 0.0, std::f64::consts::TAU);
            }
            Shape::Square => ctx.rect(x - s, y - s, 2.0 * s, 2.0 * s),
            Shape::Diamond => {
                ctx.move_to(x, y - s * 1.3);
                ctx.line_to(x + s, y);
                ctx.line_to(x, y + s * 1.3);
                ctx.line_to(x - s, y);
                ctx.close_path();
            }
            Shape::Triangle => {
                ctx.move_to(x, y - s * 1.2);
                ctx.line_to(x + s, y + s * 0.8);
                ctx.line_to(x - s, y + s * 0.8);
                ctx.close_path();
            }
            Shape::Cross => {
                ctx.move_to(x - s, y - s);
                ctx.line_to(x + s, y + s);
                ctx.move_to(x + s, y - s);
                ctx.line_to(x - s, y + s);
            }
        }
        if m.filled && m.shape != Shape::Cross {
            ctx.set_fill_style_str(m.colour);
            ctx.fill();
        } else {
            ctx.set_stroke_style_str(m.colour);
            ctx.set_line_width(1.5);
            ctx.stroke();
        }
        if m.ring > 0.0 {
            ctx.begin_path();
            let _ = ctx.arc(x, y, s + 1.0 + m.ring, 0.0, std::f64::consts::TAU);
            ctx.set_stroke_style_str("#000");
            ctx.set_line_width(m.ring.min(4.0));
            ctx.stroke();
        }
    }
    if let Some(m) = hovered.and_then(|i| marks.get(i)) {
        let (x, y) = layout.to_pixel(m.point);
        ctx.begin_path();
        let _ = ctx.arc(x, y, m.radius + 5.0, 0.0, std::f64::consts::TAU);
        ctx.set_stroke_style_str("#ff9900");
        ctx.set_line_width(2.0);
        ctx.stroke();
    }
    ctx.restore();
    // Legend, top right inside the plotting area.
    ctx.set_font("11px system-ui, sans-serif");
    ctx.set_text_align("left");
    ctx.set_text_baseline("middle");
    let width = legend
        .iter()
        .map(|(label, _)| ctx.measure_text(label).map(|m| m.width()).unwrap_or(60.0))
        .fold(0.0, f64::max)
        + 26.0;
    let x0 = r - width - 4.0;
    for (i, (label, colour)) in legend.iter().enumerate() {
        let y = t + 10.0 + 14.0 * i as f64;
        ctx.set_fill_style_str("rgba(255,255,255,0.85)");
        ctx.fill_rect(x0, y - 7.0, width, 14.0);
        ctx.set_fill_style_str(colour);
        ctx.fill_rect(x0 + 4.0, y - 4.0, 8.0, 8.0);
        ctx.set_fill_style_str("#222");
        let _ = ctx.fill_text(label, x0 + 18.0, y);
    }
}
