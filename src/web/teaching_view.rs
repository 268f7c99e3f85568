//! The page side of the teaching view: its toggle, the phase and generation buttons, slow-motion
//! play, the phase list with its one-line caption, the plot of the shown phase with hover
//! read-outs, and the orthogonal-array crossover panel. The logic lives in
//! [`crate::app::teaching`]; this file only moves it to and from the page.

use super::dom::{self, by_id, listen};
use super::page::{Ui, on_event};
use super::{oax_panel, plot_view};
use crate::app::algorithms::Algorithm;
use crate::app::oax_panel::meshes;
use crate::app::plot::{self, EAxis, Layout, PlotPoint, Scene};
use crate::app::teaching::{Step, TeachingScene, scene};
use crate::evolution::trace::Phase;
use std::cell::RefCell;
use std::rc::Rc;
use wasm_bindgen::JsCast;
use web_sys::{CanvasRenderingContext2d, HtmlButtonElement, HtmlInputElement, MouseEvent};

/// Hover radius over the teaching marks, CSS pixels.
const HIT_RADIUS: f64 = 8.0;

fn is_on() -> bool {
    dom::checked("teach")
}

fn seconds_per_phase() -> f64 {
    by_id::<HtmlInputElement>("teach-speed")
        .ok()
        .and_then(|i| i.value().parse::<f64>().ok())
        .filter(|s| s.is_finite())
        .map_or(1.5, |s| s.clamp(0.2, 10.0))
}

/// The phase the teaching view shows, if any.
pub(super) fn teaching_phase(ui: &Ui) -> Option<Phase> {
    ui.teaching.stepper.shown
}

fn teaching_applies(ui: &Ui) -> bool {
    ui.app.config().algorithm == Algorithm::Nsga2
}

/// Performs a teaching click's [`Step`].
fn teaching_step(ui: &mut Ui, step: Step) {
    if let Step::Run { generation, .. } = step
        && let Err(e) = ui.app.advance_to(generation)
    {
        dom::set_text("run-message", &e);
        ui.teaching.stepper.waiting = None;
    }
    ui.teaching.hovered = None;
}

fn teach_next_phase(ui: &mut Ui) {
    if !teaching_applies(ui) || !ui.apply_form() {
        return;
    }
    let generation = ui.app.status().generation;
    let traced = ui
        .app
        .optimizer()
        .and_then(|o| o.generation_trace())
        .map(|t| t.generation);
    let step = ui.teaching.stepper.next_phase(generation, traced);
    teaching_step(ui, step);
}

fn teach_next_generation(ui: &mut Ui) {
    if !teaching_applies(ui) || !ui.apply_form() {
        return;
    }
    let generation = ui.app.status().generation;
    let step = ui.teaching.stepper.next_generation(generation);
    teaching_step(ui, step);
}

/// The teaching view's part of a frame: arrivals, slow-motion play, caption, phase list and
/// the OAX panel.
pub(super) fn teaching_frame(ui: &mut Ui, now: f64) {
    let on = is_on();
    dom::set_visible("teaching", on);
    if !on {
        return;
    }
    for id in ["teach-phase", "teach-generation", "teach-play"] {
        if let Ok(b) = by_id::<HtmlButtonElement>(id) {
            b.set_disabled(!teaching_applies(ui));
        }
    }
    if !teaching_applies(ui) {
        dom::set_text(
            "teach-caption",
            "The teaching view follows NSGA-II: untick and tick it again to switch the method to NSGA-II.",
        );
        return;
    }
    let status = ui.app.status();
    if ui.app.reproduction().is_none() {
        follow_run(ui, status.generation, status.done);
    }
    if ui.teaching.playing
        && ui.teaching.stepper.waiting.is_none()
        && now - ui.teaching.last_auto_ms >= seconds_per_phase() * 1000.0
    {
        ui.teaching.last_auto_ms = now;
        if status.done && ui.teaching.stepper.shown == Some(Phase::Survival) {
            ui.teaching.playing = false;
        } else {
            teach_next_phase(ui);
        }
    }
    dom::set_text(
        "teach-play",
        if ui.teaching.playing { "Pause" } else { "Play" },
    );
    mark_current_phase(ui.teaching.stepper.shown);
    let caption = caption(ui);
    dom::set_text("teach-caption", &caption);
    // The OAX panel, redrawn when a new generation's crossover is there.
    let generation = status.generation;
    if ui.teaching.oax_drawn != Some(generation) && ui.app.reproduction().is_none() {
        ui.teaching.oax_drawn = Some(generation);
        let hf = ui.app.surface().heightfield.clone();
        oax_panel::show(ui.app.optimizer().and_then(|o| o.last_crossover()), &hf);
    }
}

/// Tells the stepper the run reached `generation`; a run that ended (`done`) before the
/// generation asked for stops the wait and the play.
fn follow_run(ui: &mut Ui, generation: u64, done: bool) {
    if ui.teaching.stepper.waiting.is_some() && done {
        ui.teaching.stepper.waiting = None;
        ui.teaching.playing = false;
    }
    ui.teaching.stepper.arrived(generation);
}

/// Highlights phase `shown` in the phase list.
fn mark_current_phase(shown: Option<Phase>) {
    let Ok(items) = by_id::<web_sys::Element>("teach-phases").and_then(|list| {
        list.query_selector_all("li")
            .map_err(|_| "no phase list".to_string())
    }) else {
        return;
    };
    for (i, phase) in Phase::ALL.iter().enumerate() {
        if let Some(li) = items
            .item(i as u32)
            .and_then(|n| n.dyn_into::<web_sys::Element>().ok())
        {
            let _ = li
                .class_list()
                .toggle_with_force("current", shown == Some(*phase));
        }
    }
}

/// The caption under the teaching plot: the shown phase's, or what to press or wait for.
fn caption(ui: &mut Ui) -> String {
    let traced = ui
        .app
        .optimizer()
        .is_some_and(|o| o.generation_trace().is_some());
    match (
        ui.teaching.stepper.waiting,
        traced,
        ui.teaching.stepper.shown,
    ) {
        (Some((g, _)), _, _) => format!("Computing generation {g}…"),
        (None, true, Some(_)) => teaching_scene(ui).map_or(String::new(), |s| s.caption.clone()),
        (None, true, None) => "Press “Next phase” to see the last generation's selection.".into(),
        (None, false, _) => "Press “Next phase” to make the first generation and see it \
                             phase by phase (the initial population is made first)."
            .into(),
    }
}

/// The scene of the shown phase of the last traced generation, built when either changed.
fn teaching_scene(ui: &mut Ui) -> Option<&TeachingScene> {
    let phase = ui.teaching.stepper.shown?;
    let trace = ui.app.optimizer()?.generation_trace()?;
    let key = (trace.generation, phase);
    if ui.teaching.built != Some(key) {
        let p = &ui.app.config().params;
        ui.teaching.scene = Some(scene(trace, phase, p.crossover, p.crossover_probability));
        ui.teaching.built = Some(key);
    }
    ui.teaching.scene.as_ref()
}

/// Draws the teaching plot when the view is on and has a phase to show, and returns its
/// layout; `None` otherwise (the ordinary plot is drawn).
pub(super) fn draw_teaching_plot(
    ui: &mut Ui,
    ctx: &CanvasRenderingContext2d,
    width: f64,
    height: f64,
    z_unit: &str,
) -> Option<Layout> {
    if !is_on() || !teaching_applies(ui) {
        return None;
    }
    let hovered = ui.teaching.hovered;
    let scene = teaching_scene(ui)?;
    let layout = Layout::fit_scaled(
        width,
        height,
        scene.marks.iter().map(|m| &m.point),
        dom::checked("plot-log-e"),
    );
    let empty: [PlotPoint; 0] = [];
    plot_view::draw(
        ctx,
        &layout,
        &Scene {
            population: &[],
            front: &empty,
            selected: None,
            hovered: None,
            z_unit,
            e_axis: EAxis::Sum,
            labels: &[],
        },
    );
    plot_view::draw_marks(ctx, &layout, &scene.marks, &scene.legend, hovered);
    Some(layout)
}

/// Hover over the teaching plot: the read-out under the plot. True when the teaching plot
/// is shown (the ordinary hover then does nothing).
pub(super) fn teaching_hover(ui: &mut Ui, layout: &Layout, x: f64, y: f64) -> bool {
    if !is_on() || ui.teaching.built.is_none() || ui.teaching.stepper.shown.is_none() {
        return false;
    }
    let marks = ui
        .teaching
        .scene
        .as_ref()
        .map_or(&[][..], |s| s.marks.as_slice());
    let hovered = plot::hit_test_marks(layout, marks, x, y, HIT_RADIUS);
    let text = hovered
        .and_then(|i| marks.get(i))
        .map_or(String::new(), |m| m.label.clone());
    ui.teaching.hovered = hovered;
    dom::set_text("teach-hover", &text);
    true
}

/// Shows mesh `k` of the OAX panel (see [`oax_panel::meshes`]) in the 3-D view.
fn show_oax_mesh(ui: &mut Ui, k: usize) {
    let Some(record) = ui.app.optimizer().and_then(|o| o.last_crossover()) else {
        return;
    };
    if let Some(m) = meshes(record).into_iter().nth(k) {
        ui.app.show_solution(m);
        ui.update_layers();
    }
}

/// Fills the phase list.
pub(super) fn fill() -> Result<(), String> {
    let list: web_sys::Element = by_id("teach-phases")?;
    let document = dom::document();
    for phase in Phase::ALL {
        let li = document
            .create_element("li")
            .map_err(|_| "cannot create a list item")?;
        li.set_text_content(Some(phase.label()));
        let _ = li.set_attribute("title", phase.explanation());
        let _ = list.append_child(&li);
    }
    Ok(())
}

/// The teaching view's listeners.
pub(super) fn wire(ui: &Rc<RefCell<Ui>>) -> Result<(), String> {
    let on = |id: &str, event: &str, f: fn(&mut Ui)| on_event(ui, id, event, f);
    on("teach", "change", |ui| {
        dom::set_visible("teaching", is_on());
        if is_on() {
            // Teaching goes at the teacher's pace.
            ui.app.pause();
            ui.teaching.playing = false;
            // The view follows NSGA-II: ticking it is the one action that gets there.
            if !teaching_applies(ui)
                && let Ok(menu) = by_id::<web_sys::HtmlSelectElement>("algorithm")
            {
                menu.set_value(Algorithm::Nsga2.name());
                // NSGA-II takes E_sum only.
                if let Ok(error) = by_id::<web_sys::HtmlSelectElement>("error") {
                    error.set_value("sum");
                }
                ui.apply_form();
            }
        }
    })?;
    on("teach-phase", "click", |ui| {
        ui.teaching.playing = false;
        teach_next_phase(ui);
    })?;
    on("teach-generation", "click", |ui| {
        ui.teaching.playing = false;
        teach_next_generation(ui);
    })?;
    on("teach-play", "click", |ui| {
        ui.teaching.playing = !ui.teaching.playing;
        // The first phase comes at once, the next ones after the chosen delay.
        ui.teaching.last_auto_ms = f64::NEG_INFINITY;
    })?;
    on("teach-speed", "input", |_| {
        dom::set_text(
            "teach-speed-value",
            &format!("{:.1} s", seconds_per_phase()),
        );
    })?;
    let oax: web_sys::EventTarget = by_id("oax")?;
    let u = ui.clone();
    listen(&oax, "click", move |e: MouseEvent| {
        let k = e
            .target()
            .and_then(|t| t.dyn_into::<web_sys::Element>().ok())
            .and_then(|el| el.get_attribute("data-mesh"))
            .and_then(|v| v.parse::<usize>().ok());
        if let Some(k) = k {
            show_oax_mesh(&mut u.borrow_mut(), k);
        }
    });
    Ok(())
}
