//! The compare plot: the axes of the single-run plot, then the four fronts as staircases with
//! one colour and marker shape per method, the picks ringed, the selection and the hovered
//! member marked, and a hover read-out.

use super::{COLOURS, METHODS, named_picks};
use crate::web::compare::Picks;
use crate::web::dom::{self, by_id};
use crate::web::plot::{self, Layout, PlotPoint, Scene};
use crate::web::ui::{Ui, z_unit};
use std::fmt::Write;
use wasm_bindgen::JsCast;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

impl Ui {
    /// Draws the four fronts of the comparison on `#compare-plot` and keeps the layout and the
    /// plotted members for hit-testing.
    pub(super) fn compare_plot(&mut self) {
        let Ok(canvas) = by_id::<HtmlCanvasElement>("compare-plot") else {
            return;
        };
        let dpr = web_sys::window().map_or(1.0, |w| w.device_pixel_ratio());
        let (cw, ch) = (canvas.client_width() as f64, canvas.client_height() as f64);
        let (pw, ph) = ((cw * dpr).round() as u32, (ch * dpr).round() as u32);
        if canvas.width() != pw || canvas.height() != ph {
            canvas.set_width(pw);
            canvas.set_height(ph);
        }
        let Ok(Some(ctx)) = canvas.get_context("2d") else {
            return;
        };
        let ctx: CanvasRenderingContext2d = ctx.unchecked_into();
        let _ = ctx.set_transform(dpr, 0.0, 0.0, dpr, 0.0, 0.0);
        self.compare.points.clear();
        if let Some(run) = &self.compare.run {
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
                    self.compare.points.push((k, i, p));
                }
            }
        }
        let layout = Layout::fit_scaled(
            cw,
            ch,
            self.compare.points.iter().map(|(_, _, p)| p),
            dom::checked("compare-log-e"),
        );
        let unit = z_unit(&self.app.surface().heightfield);
        // The axes, grid and titles of the single-run plot, with no data.
        plot::draw(
            &ctx,
            &layout,
            &Scene {
                population: &[],
                front: &[],
                selected: None,
                hovered: None,
                z_unit: &unit,
            },
        );
        let picks: Vec<Option<Picks>> = match self.compare.run.as_ref().and_then(|r| r.table()) {
            Some(Ok(t)) => t.methods.iter().map(|m| m.picks).collect(),
            _ => vec![None; METHODS.len()],
        };
        let (l, t, r, b) = layout.area();
        ctx.save();
        ctx.begin_path();
        ctx.rect(l, t, r - l, b - t);
        ctx.clip();
        for k in 0..METHODS.len() {
            let front: Vec<PlotPoint> = self
                .compare
                .points
                .iter()
                .filter(|(m, _, _)| *m == k)
                .map(|(_, _, p)| *p)
                .collect();
            // The staircase: the region the front dominates.
            ctx.set_stroke_style_str(COLOURS[k]);
            ctx.set_fill_style_str(COLOURS[k]);
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
            for p in &front {
                let (x, y) = layout.to_pixel(*p);
                marker(&ctx, k, x, y, 3.5);
                ctx.fill();
            }
            // The picks: a ring in the method's colour.
            if let Some(p) = &picks[k] {
                ctx.set_line_width(2.0);
                for (_, pick) in named_picks(p) {
                    let (x, y) = layout.to_pixel(PlotPoint {
                        t: pick.t as f64,
                        e: pick.e,
                    });
                    ctx.begin_path();
                    let _ = ctx.arc(x, y, 8.0, 0.0, std::f64::consts::TAU);
                    ctx.stroke();
                }
            }
        }
        // The selection (on every front that has it) and the hovered member.
        if let Some(sel) = self.app.selected() {
            ctx.set_stroke_style_str("#000000");
            ctx.set_line_width(2.0);
            for (_, _, p) in &self.compare.points {
                if p.t == sel.t as f64 && p.e == sel.e_sum {
                    let (x, y) = layout.to_pixel(*p);
                    ctx.begin_path();
                    let _ = ctx.arc(x, y, 11.0, 0.0, std::f64::consts::TAU);
                    ctx.stroke();
                }
            }
        }
        let hovered = self
            .compare
            .hovered
            .and_then(|h| self.compare.points.get(h));
        if let Some((_, _, p)) = hovered {
            let (x, y) = layout.to_pixel(*p);
            ctx.set_stroke_style_str("#ff0000");
            ctx.set_line_width(2.0);
            ctx.begin_path();
            let _ = ctx.arc(x, y, 6.0, 0.0, std::f64::consts::TAU);
            ctx.stroke();
        }
        ctx.restore();
        if let Some(&(k, _, p)) = hovered {
            let mut text = format!(
                "{} · T = {}, E = {}",
                METHODS[k].label(),
                p.t,
                plot::format_value(p.e)
            );
            if let Some(picks) = &picks[k] {
                for (name, pick) in named_picks(picks) {
                    if super::is_pick(&pick, p.t, p.e) {
                        let _ = write!(text, " · {name}");
                    }
                }
            }
            readout(&ctx, &layout, p, &text);
        }
        self.compare.layout = Some(layout);
    }
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

fn readout(ctx: &CanvasRenderingContext2d, layout: &Layout, p: PlotPoint, text: &str) {
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
