//! Compare mode in the page: the toggle and buttons of the `#compare` fieldset, the plot of the
//! fronts (`#compare-plot`), the live tables and click-to-select into the 3-D view. The
//! logic is [`CompareRun`]; this is its DOM.

use super::costs::performance_now;
use super::dom::{self, by_id, listen};
use super::page::{CompareView, HIT_RADIUS, Ui, on_event};
use crate::app::compare::CompareRun;
use crate::app::compare_html::{legend_html, method_index, note_text, table_html};
use crate::app::plot::{self, PlotPoint};
use crate::experiment::{Method, Pick};
use crate::front::Solution;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use web_sys::{HtmlCanvasElement, MouseEvent};

mod draw;

/// True when the member at (`t`, `e`) is `pick` (a pick is a member: exact equality holds).
fn is_pick(pick: &Pick, t: f64, e: f64) -> bool {
    pick.t as f64 == t && pick.e == e
}

fn set_html(id: &str, html: &str) {
    if let Ok(e) = by_id::<web_sys::Element>(id) {
        e.set_inner_html(html);
    }
}

/// Compare mode's part of a frame: advance the run within the budget, refresh the table
/// (throttled), and draw every method's front.
pub(super) fn compare_frame(ui: &mut Ui) {
    let surface = Arc::as_ptr(&ui.app.surface().heightfield);
    if ui
        .compare
        .run
        .as_ref()
        .is_some_and(|r| Arc::as_ptr(&r.surface().heightfield) != surface)
    {
        // A new surface: the comparison belonged to the old one.
        compare_reset(ui);
        dom::set_text(
            "compare-message",
            "the surface changed: press Compare to run every method on it",
        );
    }
    if !dom::checked("compare-on") {
        return;
    }
    let budget = ui.app.config().budget_ms;
    if let Some(run) = ui.compare.run.as_mut() {
        let mut clock = performance_now;
        let tick = run.tick(budget, &mut clock);
        let pick = tick.finished.then(|| run.trade_off_solution()).flatten();
        if run.refresh_table(performance_now()) {
            compare_table(ui);
        }
        if let Some(pick) = pick
            && ui.app.select_if_unselected(pick)
        {
            ui.update_layers();
        }
    }
    compare_status(ui);
    draw::compare_plot(ui);
}

fn compare_reset(ui: &mut Ui) {
    ui.compare = CompareView::default();
    for id in ["compare-methods", "compare-picks", "compare-pairs"] {
        set_html(id, "");
    }
    dom::set_text("compare-note", "");
    compare_status(ui);
}

/// Starts (or resumes) the comparison with the form's parameters; a run with other
/// parameters or on another surface is replaced. The single run pauses: they would share
/// the frame budget.
fn compare_start(ui: &mut Ui) {
    let params = match dom::read_config() {
        Ok(c) => c.params,
        Err(e) => {
            dom::set_text("compare-message", &e);
            return;
        }
    };
    let surface = ui.app.surface().clone();
    let reuse = ui.compare.run.as_ref().is_some_and(|r| {
        r.params() == &params && Arc::ptr_eq(&r.surface().heightfield, &surface.heightfield)
    });
    if !reuse {
        compare_reset(ui);
        match CompareRun::new(surface, params) {
            Ok(run) => ui.compare.run = Some(run),
            Err(e) => {
                dom::set_text("compare-message", &e);
                return;
            }
        }
    }
    dom::set_text("compare-message", "");
    ui.app.pause();
    if let Some(run) = ui.compare.run.as_mut() {
        run.run();
    }
}

/// Turns compare mode on (its panel replaces the single-run plot) or off (the comparison
/// pauses; it resumes with Compare).
fn compare_mode(ui: &mut Ui, on: bool) {
    if let Ok(input) = by_id::<web_sys::HtmlInputElement>("compare-on") {
        input.set_checked(on);
    }
    if let Ok(right) = by_id::<web_sys::Element>("right") {
        let _ = right.class_list().toggle_with_force("comparing", on);
    }
    dom::set_visible("compare-body", on);
    super::page::show_parameters();
    if !on {
        compare_pause(ui);
    }
    compare_status(ui);
}

fn compare_pause(ui: &mut Ui) {
    if let Some(run) = ui.compare.run.as_mut() {
        run.pause();
    }
}

fn compare_status(ui: &Ui) {
    let text = match &ui.compare.run {
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

fn compare_table(ui: &Ui) {
    let Some(run) = &ui.compare.run else {
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
fn compare_select(ui: &mut Ui, k: usize, index: usize) {
    let chosen: Option<Solution> = ui
        .compare
        .run
        .as_ref()
        .and_then(|r| r.front(k))
        .and_then(|f| f.solutions().get(index).cloned());
    if chosen.is_some() {
        ui.app.select_solution(chosen);
        ui.update_layers();
    }
}

fn compare_hit(ui: &Ui, x: f64, y: f64) -> Option<usize> {
    let layout = ui.compare.layout.as_ref()?;
    let points: Vec<PlotPoint> = ui.compare.points.iter().map(|(_, _, p)| *p).collect();
    plot::hit_test(layout, &points, x, y, HIT_RADIUS)
}

/// Wires the compare panel's controls.
pub(super) fn wire(ui: &Rc<RefCell<Ui>>) -> Result<(), String> {
    set_html("compare-legend", &legend_html());
    let on = |id: &str, event: &str, f: Box<dyn Fn(&mut Ui)>| on_event(ui, id, event, f);
    on(
        "compare-on",
        "change",
        Box::new(|ui| compare_mode(ui, dom::checked("compare-on"))),
    )?;
    on("compare-run", "click", Box::new(compare_start))?;
    on("compare-pause", "click", Box::new(compare_pause))?;
    on("compare-reset", "click", Box::new(compare_reset))?;
    // The single run and the comparison would share the frame budget: starting the single run
    // pauses the comparison and brings the single-run plot back.
    for id in ["run", "step"] {
        on(id, "click", Box::new(|ui| compare_mode(ui, false)))?;
    }
    let plot: HtmlCanvasElement = by_id("compare-plot")?;
    let u = ui.clone();
    listen(&plot, "mousemove", move |e: MouseEvent| {
        let mut ui = u.borrow_mut();
        ui.compare.hovered = compare_hit(&ui, e.offset_x() as f64, e.offset_y() as f64);
    });
    let u = ui.clone();
    listen(&plot, "mouseleave", move |_: MouseEvent| {
        u.borrow_mut().compare.hovered = None
    });
    let u = ui.clone();
    listen(&plot, "click", move |e: MouseEvent| {
        let mut ui = u.borrow_mut();
        if let Some(h) = compare_hit(&ui, e.offset_x() as f64, e.offset_y() as f64) {
            let (k, i, _) = ui.compare.points[h];
            compare_select(&mut ui, k, i);
        }
    });
    // A click on a pick in the table shows that mesh.
    let picks: web_sys::EventTarget = by_id("compare-picks")?;
    let u = ui.clone();
    listen(&picks, "click", move |e: MouseEvent| {
        if let Some((k, t, e_sum)) = clicked_pick(&e) {
            select_pick(&mut u.borrow_mut(), k, t, e_sum);
        }
    });
    Ok(())
}

/// The pick cell under click `e`: its method's index in [`METHODS`](crate::app::compare::METHODS)
/// and its T and E.
fn clicked_pick(e: &MouseEvent) -> Option<(usize, f64, f64)> {
    let cell = e
        .target()
        .and_then(|t| t.dyn_into::<web_sys::Element>().ok())
        .and_then(|t| t.closest("td[data-pick]").ok().flatten())?;
    let method = cell
        .closest("tr[data-method]")
        .ok()
        .flatten()
        .and_then(|r| r.get_attribute("data-method"))
        .and_then(|m| Method::parse(&m).ok())?;
    let number = |name: &str| cell.get_attribute(name).and_then(|v| v.parse::<f64>().ok());
    Some((method_index(method), number("data-t")?, number("data-e")?))
}

/// Shows the member of method `k`'s front with `t` triangles and error `e_sum`, if it is there.
fn select_pick(ui: &mut Ui, k: usize, t: f64, e_sum: f64) {
    let index = ui
        .compare
        .run
        .as_ref()
        .and_then(|r| r.front(k))
        .and_then(|f| {
            f.solutions()
                .iter()
                .position(|s| s.t as f64 == t && s.e_sum == e_sum)
        });
    if let Some(i) = index {
        compare_select(ui, k, i);
    }
}
