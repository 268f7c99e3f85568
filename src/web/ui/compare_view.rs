//! Compare mode in the page: the toggle and buttons of the `#compare` fieldset, the plot of the
//! four fronts (`#compare-plot`), the live tables, click-to-select into the 3-D view, and the
//! read-only accessors the end-to-end test uses. The logic is [`CompareRun`]; this is its DOM.

use super::super::compare::{CompareRun, METHODS, Picks};
use super::super::plot::{self, Layout, PlotPoint};
use super::{HIT_RADIUS, Ui, WebApp, on_event, performance_now};
use crate::experiment::{Method, Pick};
use crate::front::Solution;
use crate::web::dom::{self, by_id, listen};
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;
use web_sys::{HtmlCanvasElement, MouseEvent};

mod draw;
mod html;

use html::{legend_html, note_text, table_html};

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

/// Position of `m` in [`METHODS`] (the order of colours, shapes and fronts).
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

/// True when the member at (`t`, `e`) is `pick` (a pick is a member: exact equality holds).
fn is_pick(pick: &Pick, t: f64, e: f64) -> bool {
    pick.t as f64 == t && pick.e == e
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

/// Wires the compare panel's controls.
pub(super) fn wire(ui: &Rc<RefCell<Ui>>) -> Result<(), String> {
    set_html("compare-legend", &legend_html());
    let on = |id: &str, event: &str, f: Box<dyn Fn(&mut Ui)>| on_event(ui, id, event, f);
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
}
