//! Compare mode in the page: the toggle and buttons of the `#compare` fieldset, the plot of the
//! four fronts (`#compare-plot`), the live tables, click-to-select into the 3-D view, and the
//! read-only accessors the end-to-end test uses. The logic is [`CompareRun`]; this is its DOM.

use super::super::compare::{CompareRun, CompareTable, METHODS, Picks};
use super::super::plot::{self, Layout, PlotPoint, Scene};
use super::{HIT_RADIUS, Ui, WebApp, performance_now, z_unit};
use crate::experiment::{Method, Pick};
use crate::front::Solution;
use crate::web::dom::{self, by_id, listen};
use std::cell::RefCell;
use std::fmt::Write;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement, MouseEvent};

/// Okabe–Ito colours (distinguishable with the common colour-vision deficiencies), one per
/// method in [`METHODS`] order; each method also has its own marker shape.
const COLOURS: [&str; 4] = ["#0072B2", "#E69F00", "#009E73", "#CC79A7"];

/// Marker shapes, in [`METHODS`] order, as the legend names them.
const SHAPES: [&str; 4] = ["●", "■", "▲", "◆"];

/// Short method names for the tables (the legend gives the full ones), so that the tables fit
/// the page's right column.
const SHORT: [&str; 4] = ["NSGA-II", "Weighted", "Decimation", "Greedy"];

/// The compare panel's state.
#[derive(Default)]
pub(super) struct CompareView {
    run: Option<CompareRun>,
    layout: Option<Layout>,
    /// Every plotted member: (method index, index in its front, position).
    points: Vec<(usize, usize, PlotPoint)>,
    hovered: Option<usize>,
}

fn method_index(m: Method) -> usize {
    METHODS.iter().position(|&x| x == m).unwrap_or(0)
}

/// The three picks with their names, for marks and read-outs.
fn named_picks(p: &Picks) -> [(&'static str, Pick); 3] {
    [
        ("best error", p.best_error),
        ("fewest triangles", p.fewest_triangles),
        ("trade-off", p.trade_off),
    ]
}

fn is_pick(pick: &Pick, t: f64, e: f64) -> bool {
    pick.t as f64 == t && pick.e == e
}

fn fmt_opt(v: Option<f64>, digits: usize) -> (String, String) {
    match v {
        Some(x) => (format!("{x:.digits$}"), format!("{x}")),
        None => ("—".to_string(), String::new()),
    }
}

/// The rows of the three tables, as HTML (numbers and fixed labels only: nothing to escape).
/// Each number cell carries its full-precision value in `data-value`.
fn table_html(table: &CompareTable) -> (String, String, String) {
    let mut methods = String::new();
    let mut picks = String::new();
    let name = |m: Method| {
        let k = method_index(m);
        format!(
            "<span class=\"mark\" style=\"color:{}\">{}</span> {}",
            COLOURS[k], SHAPES[k], SHORT[k]
        )
    };
    for row in &table.methods {
        let (hvr, hvr_value) = fmt_opt(row.hvr, 4);
        let _ = write!(
            methods,
            "<tr data-method=\"{}\"><th>{}</th><td>{}</td><td>{}</td><td>{}</td><td data-value=\"{hvr_value}\">{hvr}</td></tr>",
            row.method.name(),
            name(row.method),
            if row.done { "done" } else { "in progress" },
            row.evaluations,
            row.front_size,
        );
        let _ = write!(
            picks,
            "<tr data-method=\"{}\"><th>{}</th>",
            row.method.name(),
            name(row.method)
        );
        match &row.picks {
            Some(p) => {
                for (kind, pick) in named_picks(p) {
                    let _ = write!(
                        picks,
                        "<td class=\"pick\" data-pick=\"{kind}\" data-e=\"{}\" data-t=\"{}\" title=\"click to show this mesh\">{} / {}</td>",
                        pick.e,
                        pick.t,
                        plot::format_value(pick.e),
                        pick.t
                    );
                }
            }
            None => picks.push_str("<td>—</td><td>—</td><td>—</td>"),
        }
        picks.push_str("</tr>");
    }
    let mut pairs = String::new();
    for row in &table.pairs {
        let (eps, eps_value) = fmt_opt(row.epsilon, 4);
        let (cov, cov_value) = fmt_opt(row.coverage, 3);
        let _ = write!(
            pairs,
            "<tr data-a=\"{}\" data-b=\"{}\"><th>{}</th><th>{}</th><td data-value=\"{eps_value}\">{eps}</td><td data-value=\"{cov_value}\">{cov}</td></tr>",
            row.a.name(),
            row.b.name(),
            name(row.a),
            name(row.b),
        );
    }
    (methods, picks, pairs)
}

fn note_text(table: &CompareTable) -> String {
    let n = table.normalization;
    format!(
        "One normalisation for the four fronts: E ÷ {} (E of the corner-only mesh), T ÷ {} (the full \
         grid's triangles). HVR = hypervolume of the front ÷ that of the reference front (the \
         non-dominated merge of the four fronts, {} points), reference point ({}, {}). ε+ in \
         normalised units; C(A, B) = share of B's points weakly dominated by A's. Trade-off pick: \
         eq. 7–9 with 1000 weights from seed {}. The same computation as `paretomesh experiment`. {}",
        plot::format_value(n.e_scale()),
        n.t_scale(),
        table.reference_front_size,
        table.reference_point[0],
        table.reference_point[1],
        table.seed,
        if table.complete {
            "Final: all four methods are done."
        } else {
            "Live: updated at most 4 times a second until all four are done."
        }
    )
}

fn set_html(id: &str, html: &str) {
    if let Ok(e) = by_id::<web_sys::Element>(id) {
        e.set_inner_html(html);
    }
}

impl Ui {
    /// Compare mode's part of a frame: advance the run within the budget, refresh the table
    /// (throttled), and draw the four fronts.
    pub(super) fn compare_frame(&mut self) {
        let surface = Arc::as_ptr(&self.app.surface().heightfield);
        if self
            .compare
            .run
            .as_ref()
            .is_some_and(|r| Arc::as_ptr(&r.surface().heightfield) != surface)
        {
            // A new surface: the comparison belonged to the old one.
            self.compare_reset();
            dom::set_text(
                "compare-message",
                "the surface changed: press Compare to run the four methods on it",
            );
        }
        if !dom::checked("compare-on") {
            return;
        }
        let budget = self.app.config().budget_ms;
        if let Some(run) = self.compare.run.as_mut() {
            let mut clock = performance_now;
            run.tick(budget, &mut clock);
            if run.refresh_table(performance_now()) {
                self.compare_table();
            }
        }
        self.compare_status();
        self.compare_plot();
    }

    fn compare_reset(&mut self) {
        self.compare = CompareView::default();
        for id in ["compare-methods", "compare-picks", "compare-pairs"] {
            set_html(id, "");
        }
        dom::set_text("compare-note", "");
        self.compare_status();
    }

    /// Starts (or resumes) the comparison with the form's parameters; a run with other
    /// parameters or on another surface is replaced. The single run pauses: they would share
    /// the frame budget.
    fn compare_start(&mut self) {
        let params = match dom::read_config() {
            Ok(c) => c.params,
            Err(e) => {
                dom::set_text("compare-message", &e);
                return;
            }
        };
        let surface = self.app.surface().clone();
        let reuse = self.compare.run.as_ref().is_some_and(|r| {
            r.params() == &params && Arc::ptr_eq(&r.surface().heightfield, &surface.heightfield)
        });
        if !reuse {
            self.compare_reset();
            match CompareRun::new(surface, params) {
                Ok(run) => self.compare.run = Some(run),
                Err(e) => {
                    dom::set_text("compare-message", &e);
                    return;
                }
            }
        }
        dom::set_text("compare-message", "");
        self.app.pause();
        if let Some(run) = self.compare.run.as_mut() {
            run.run();
        }
    }

    /// Turns compare mode on (its panel replaces the single-run plot) or off (the comparison
    /// pauses; it resumes with Compare).
    fn compare_mode(&mut self, on: bool) {
        if let Ok(input) = by_id::<web_sys::HtmlInputElement>("compare-on") {
            input.set_checked(on);
        }
        if let Ok(right) = by_id::<web_sys::Element>("right") {
            let _ = right.class_list().toggle_with_force("comparing", on);
        }
        dom::set_visible("compare-body", on);
        if !on {
            self.compare_pause();
        }
        self.compare_status();
    }

    fn compare_pause(&mut self) {
        if let Some(run) = self.compare.run.as_mut() {
            run.pause();
        }
    }

    fn compare_status(&self) {
        let text = match &self.compare.run {
            None => "not started: press Compare".to_string(),
            Some(run) => {
                let (evaluations, ms) = run.totals();
                let state = if run.is_done() {
                    "done"
                } else if run.is_running() {
                    "running"
                } else {
                    "paused"
                };
                let p = run.params();
                format!(
                    "{state} · {evaluations} evaluations in {:.1} s · GA population {}, {} generations, seed {}",
                    ms / 1000.0,
                    p.population,
                    p.generations,
                    p.seed
                )
            }
        };
        dom::set_text("compare-status", &text);
    }

    fn compare_table(&self) {
        let Some(run) = &self.compare.run else {
            return;
        };
        match run.table() {
            Some(Ok(table)) => {
                let (methods, picks, pairs) = table_html(table);
                set_html("compare-methods", &methods);
                set_html("compare-picks", &picks);
                set_html("compare-pairs", &pairs);
                dom::set_text("compare-note", &note_text(table));
            }
            Some(Err(e)) => dom::set_text("compare-note", &format!("no indicators: {e}")),
            None => {}
        }
    }

    fn compare_plot(&mut self) {
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
                    if is_pick(&pick, p.t, p.e) {
                        let _ = write!(text, " · {name}");
                    }
                }
            }
            readout(&ctx, &layout, p, &text);
        }
        self.compare.layout = Some(layout);
    }

    /// Shows member `index` of method `k`'s front in the 3-D view.
    fn compare_select(&mut self, k: usize, index: usize) {
        let chosen: Option<Solution> = self
            .compare
            .run
            .as_ref()
            .and_then(|r| r.front(k))
            .and_then(|f| f.solutions().get(index).cloned());
        if chosen.is_some() {
            self.app.select_solution(chosen);
            self.update_layers();
        }
    }

    fn compare_hit(&self, x: f64, y: f64) -> Option<usize> {
        let layout = self.compare.layout.as_ref()?;
        let points: Vec<PlotPoint> = self.compare.points.iter().map(|(_, _, p)| *p).collect();
        plot::hit_test(layout, &points, x, y, HIT_RADIUS)
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

/// The legend under the compare plot.
fn legend_html() -> String {
    let mut html = String::new();
    for (k, m) in METHODS.iter().enumerate() {
        let _ = write!(
            html,
            "<li><span class=\"mark\" style=\"color:{}\">{}</span> {}</li>",
            COLOURS[k],
            SHAPES[k],
            m.label()
        );
    }
    html.push_str("<li><span class=\"ring\"></span> the three picks</li>");
    html
}

/// Wires the compare panel's controls.
pub(super) fn wire(ui: &Rc<RefCell<Ui>>) -> Result<(), String> {
    set_html("compare-legend", &legend_html());
    let on = |id: &str, event: &str, f: Box<dyn Fn(&mut Ui)>| -> Result<(), String> {
        let ui = ui.clone();
        let target: web_sys::EventTarget = by_id(id)?;
        listen(&target, event, move |_: web_sys::Event| {
            f(&mut ui.borrow_mut())
        });
        Ok(())
    };
    on(
        "compare-on",
        "change",
        Box::new(|ui| ui.compare_mode(dom::checked("compare-on"))),
    )?;
    on("compare-run", "click", Box::new(|ui| ui.compare_start()))?;
    on("compare-pause", "click", Box::new(|ui| ui.compare_pause()))?;
    on("compare-reset", "click", Box::new(|ui| ui.compare_reset()))?;
    // The single run and the comparison would share the frame budget: starting the single run
    // pauses the comparison and brings the single-run plot back.
    for id in ["run", "step"] {
        on(id, "click", Box::new(|ui| ui.compare_mode(false)))?;
    }
    let plot: HtmlCanvasElement = by_id("compare-plot")?;
    let u = ui.clone();
    listen(&plot, "mousemove", move |e: MouseEvent| {
        let mut ui = u.borrow_mut();
        ui.compare.hovered = ui.compare_hit(e.offset_x() as f64, e.offset_y() as f64);
    });
    let u = ui.clone();
    listen(&plot, "mouseleave", move |_: MouseEvent| {
        u.borrow_mut().compare.hovered = None
    });
    let u = ui.clone();
    listen(&plot, "click", move |e: MouseEvent| {
        let mut ui = u.borrow_mut();
        if let Some(h) = ui.compare_hit(e.offset_x() as f64, e.offset_y() as f64) {
            let (k, i, _) = ui.compare.points[h];
            ui.compare_select(k, i);
        }
    });
    // A click on a pick in the table shows that mesh.
    let picks: web_sys::EventTarget = by_id("compare-picks")?;
    let u = ui.clone();
    listen(&picks, "click", move |e: MouseEvent| {
        let Some(cell) = e
            .target()
            .and_then(|t| t.dyn_into::<web_sys::Element>().ok())
            .and_then(|t| t.closest("td[data-pick]").ok().flatten())
        else {
            return;
        };
        let Some(method) = cell
            .closest("tr[data-method]")
            .ok()
            .flatten()
            .and_then(|r| r.get_attribute("data-method"))
            .and_then(|m| Method::parse(&m).ok())
        else {
            return;
        };
        let number = |name: &str| cell.get_attribute(name).and_then(|v| v.parse::<f64>().ok());
        let (Some(e_value), Some(t_value)) = (number("data-e"), number("data-t")) else {
            return;
        };
        let mut ui = u.borrow_mut();
        let k = method_index(method);
        let index = ui
            .compare
            .run
            .as_ref()
            .and_then(|r| r.front(k))
            .and_then(|f| {
                f.solutions()
                    .iter()
                    .position(|s| s.t as f64 == t_value && s.e_sum == e_value)
            });
        if let Some(i) = index {
            ui.compare_select(k, i);
        }
    });
    Ok(())
}

/// Read-only views of compare mode for the console and the end-to-end test.
#[wasm_bindgen]
impl WebApp {
    /// Members of each method's front in compare mode, in the table's order (NSGA-II,
    /// weighted-sum GA, decimation, greedy insertion); empty before a comparison starts.
    #[wasm_bindgen(js_name = compareFrontLengths)]
    pub fn compare_front_lengths(&self) -> Vec<u32> {
        let ui = self.ui.borrow();
        ui.compare.run.as_ref().map_or(Vec::new(), |r| {
            (0..METHODS.len())
                .map(|k| r.front(k).map_or(0, |f| f.len() as u32))
                .collect()
        })
    }

    /// True once all four methods of the comparison have finished.
    #[wasm_bindgen(js_name = compareDone)]
    pub fn compare_done(&self) -> bool {
        self.ui
            .borrow()
            .compare
            .run
            .as_ref()
            .is_some_and(|r| r.is_done())
    }

    /// The last computed table as JSON (`{"error": …}` if it could not be computed); `None`
    /// before the first.
    #[wasm_bindgen(js_name = compareTable)]
    pub fn compare_table(&self) -> Option<String> {
        let ui = self.ui.borrow();
        let table = ui.compare.run.as_ref()?.table()?;
        Some(match table {
            Ok(t) => serde_json::to_string(t).unwrap_or_default(),
            Err(e) => serde_json::json!({ "error": e }).to_string(),
        })
    }

    /// Evaluations and optimisation milliseconds of the comparison, summed over the methods.
    #[wasm_bindgen(js_name = compareTotals)]
    pub fn compare_totals(&self) -> Vec<f64> {
        let ui = self.ui.borrow();
        ui.compare.run.as_ref().map_or(vec![0.0, 0.0], |r| {
            let (e, ms) = r.totals();
            vec![e as f64, ms]
        })
    }

    /// CSS-pixel position in `#compare-plot` of member `index` of method `method`'s front (in
    /// the table's order), as of the last frame.
    #[wasm_bindgen(js_name = comparePointPosition)]
    pub fn compare_point_position(&self, method: usize, index: usize) -> Option<Vec<f64>> {
        let ui = self.ui.borrow();
        let layout = ui.compare.layout.as_ref()?;
        let (_, _, p) = ui
            .compare
            .points
            .iter()
            .find(|(k, i, _)| *k == method && *i == index)?;
        let (x, y) = layout.to_pixel(*p);
        Some(vec![x, y])
    }

    /// The selected solution's (T, E), if any.
    #[wasm_bindgen(js_name = selectedObjectives)]
    pub fn selected_objectives(&self) -> Option<Vec<f64>> {
        let ui = self.ui.borrow();
        ui.app.selected().map(|s| vec![s.t as f64, s.e_sum])
    }
}
