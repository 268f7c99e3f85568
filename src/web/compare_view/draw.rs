//! The compare plot: the axes of the single-run plot, then every method's front as a staircase with
//! one colour and marker shape per method, the picks ringed, the selection and the hovered
//! member marked, and a hover read-out.

use crate::app::compare::{METHODS, Picks};
use crate::app::compare_html::{colour, named_picks};
use crate::app::plot::{self, EAxis, Layout, PlotPoint, Scene};
use crate::web::dom;
use crate::web::page::{Ui, z_unit};
use crate::web::plot_view;
use std::fmt::Write;
use web_sys::CanvasRenderingContext2d;

/// Draws every method's front of the comparison on `#compare-plot` and keeps the layout and the
/// plotted members for hit-testing.
pub(super) fn compare_plot(ui: &mut Ui) {
    let Some((ctx, cw, ch)) = dom::canvas_2d("compare-plot") else {
        return;
    };
    list_points(ui);
    let layout = Layout::fit_scaled(
        cw,
        ch,
        ui.compare.points.iter().map(|(_, _, p)| p),
        dom::checked("compare-log-e"),
    );
    let unit = z_unit(&ui.app.surface().heightfield);
    // The axes, grid and titles of the single-run plot, with no data.
    plot_view::draw(
        &ctx,
        &layout,
        &Scene {
            population: &[],
            front: &[],
            selected: None,
            hovered: None,
            z_unit: &unit,
            e_axis: EAxis::Sum,
            labels: &[],
        },
    );
    let picks: Vec<Option<Picks>> = match ui.compare.run.as_ref().and_then(|r| r.table()) {
        Some(Ok(t)) => t.methods.iter().map(|m| m.picks).collect(),
        _ => vec![None; METHODS.len()],
    };
    let (l, t, r, b) = layout.area();
    ctx.save();
    ctx.begin_path();
    ctx.rect(l, t, r - l, b - t);
    ctx.clip();
    for (k, method_picks) in picks.iter().enumerate() {
        let front: Vec<PlotPoint> = ui
            .compare
            .points
            .iter()
            .filter(|(m, _, _)| *m == k)
            .map(|(_, _, p)| *p)
            .collect();
        draw_front(&ctx, &layout, k, &front, method_picks.as_ref());
    }
    // The selection (on every front that has it) and the hovered member.
    if let Some(sel) = ui.app.selected() {
        ctx.set_stroke_style_str("#000000");
        ctx.set_line_width(2.0);
        for (_, _, p) in &ui.compare.points {
            if p.t == sel.t as f64 && p.e == sel.e_sum {
                ring(&ctx, layout.to_pixel(*p), 11.0);
            }
        }
    }
    let hovered = ui.compare.hovered.and_then(|h| ui.compare.points.get(h));
    if let Some((_, _, p)) = hovered {
        ctx.set_stroke_style_str("#ff0000");
        ctx.set_line_width(2.0);
        ring(&ctx, layout.to_pixel(*p), 6.0);
    }
    ctx.restore();
    if let Some(&(k, _, p)) = hovered {
        plot_view::readout(&ctx, &layout, p, &readout_text(k, p, picks[k].as_ref()));
    }
    ui.compare.layout = Some(layout);
}

/// Lists every method's front members in `ui.compare.points` as (method, index, point).
fn list_points(ui: &mut Ui) {
    ui.compare.points.clear();
    if let Some(run) = &ui.compare.run {
        for k in 0..METHODS.len() {
            for (i, s) in run
                .front(k)
                .map_or(&[][..], |f| f.solutions())
                .iter()
                .enumerate()
            {
                let p = PlotPoint {
                    t: s.t as f64,
                    e: s.e_sum,
                };
                ui.compare.points.push((k, i, p));
            }
        }
    }
}

/// Method `k`'s `front` in its colour: the staircase of the region it dominates, a marker per
/// member and a ring around each of its `picks`.
fn draw_front(
    ctx: &CanvasRenderingContext2d,
    layout: &Layout,
    k: usize,
    front: &[PlotPoint],
    picks: Option<&Picks>,
) {
    ctx.set_stroke_style_str(colour(k));
    ctx.set_fill_style_str(colour(k));
    ctx.set_line_width(1.5);
    ctx.begin_path();
    for (i, p) in front.iter().enumerate() {
        let (x, y) = layout.to_pixel(*p);
        if i == 0 {
            ctx.move_to(x, y);
        } else {
            let (_, prev_y) = layout.to_pixel(front[i - 1]);
            ctx.line_to(x, prev_y);
            ctx.line_to(x, y);
        }
    }
    ctx.stroke();
    for p in front {
        let (x, y) = layout.to_pixel(*p);
        marker(ctx, k, x, y, 3.5);
        ctx.fill();
    }
    if let Some(p) = picks {
        ctx.set_line_width(2.0);
        for (_, pick) in named_picks(p) {
            let at = layout.to_pixel(PlotPoint {
                t: pick.t as f64,
                e: pick.e,
            });
            ring(ctx, at, 8.0);
        }
    }
}

/// Strokes a circle of `radius` around the pixel `(x, y)`.
fn ring(ctx: &CanvasRenderingContext2d, (x, y): (f64, f64), radius: f64) {
    ctx.begin_path();
    let _ = ctx.arc(x, y, radius, 0.0, std::f64::consts::TAU);
    ctx.stroke();
}

/// The hover read-out of method `k`'s member at `p`, naming the picks it is.
fn readout_text(k: usize, p: PlotPoint, picks: Option<&Picks>) -> String {
    let mut text = format!(
        "{} · T = {}, E = {}",
        METHODS[k].label(),
        p.t,
        plot::format_value(p.e)
    );
    if let Some(picks) = picks {
        for (name, pick) in named_picks(picks) {
            if super::is_pick(&pick, p.t, p.e) {
                let _ = write!(text, " · {name}");
            }
        }
    }
    text
}

/// Traces method `k`'s marker shape at (`x`, `y`) with half-size `r` (call fill or stroke).
fn marker(ctx: &CanvasRenderingContext2d, k: usize, x: f64, y: f64, r: f64) {
    ctx.begin_path();
    match k {
        0 => {
            let _ = ctx.arc(x, y, r, 0.0, std::f64::consts::TAU);
        }
        1 => ctx.rect(x - r * 0.9, y - r * 0.9, 1.8 * r, 1.8 * r),
        2 => {
            ctx.move_to(x, y - 1.2 * r);
            ctx.line_to(x + 1.1 * r, y + 0.8 * r);
            ctx.line_to(x - 1.1 * r, y + 0.8 * r);
            ctx.close_path();
        }
        _ => {
            ctx.move_to(x, y - 1.3 * r);
            ctx.line_to(x + 1.1 * r, y);
            ctx.line_to(x, y + 1.3 * r);
            ctx.line_to(x - 1.1 * r, y);
            ctx.close_path();
        }
    }
}
