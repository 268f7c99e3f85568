//! The page side of the teaching view: its toggle, the phase and generation buttons, slow-motion
//! play, the phase list with its one-line caption, the plot of the shown phase with hover
//! read-outs, and the orthogonal-array crossover panel. The logic lives in
//! [`super::teaching`]; this file only moves it to and from the page.

use super::algorithms::Algorithm;
use super::dom::{self, by_id, listen};
use super::oax_panel;
use super::plot::{self, Layout, PlotPoint, Scene};
use super::teaching::{Step, Stepper, TeachingScene, scene};
use super::ui::{Ui, on_event};
use crate::evolution::trace::Phase;
use std::cell::RefCell;
use std::rc::Rc;
use wasm_bindgen::JsCast;
use web_sys::{CanvasRenderingContext2d, HtmlButtonElement, HtmlInputElement, MouseEvent};

/// Hover radius over the teaching marks, CSS pixels.
const HIT_RADIUS: f64 = 8.0;

/// The teaching view's page state.
#[derive(Default)]
pub struct TeachingUi {
    stepper: Stepper,
    /// The shown phase's marks, legend and caption, built once per (generation, phase).
    scene: Option<TeachingScene>,
    hovered: Option<usize>,
    playing: bool,
    /// When play last advanced a phase (ms, performance clock).
    last_auto_ms: f64,
    /// The crossover generation the OAX panel was drawn for.
    oax_drawn: Option<u64>,
    /// The (generation, phase) `scene` was built for.
    built: Option<(u64, Phase)>,
}

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

impl Ui {
    /// The phase the teaching view shows, if any.
    pub(super) fn teaching_phase(&self) -> Option<Phase> {
        self.teaching.stepper.shown
    }

    fn teaching_applies(&self) -> bool {
        self.app.config().algorithm == Algorithm::Nsga2
    }

    /// Performs a teaching click's [`Step`].
    fn teaching_step(&mut self, step: Step) {
        if let Step::Run { generation, .. } = step
            && let Err(e) = self.app.advance_to(generation)
        {
            dom::set_text("run-message", &e);
            self.teaching.stepper.waiting = None;
        }
        self.teaching.hovered = None;
    }

    fn teach_next_phase(&mut self) {
        if !self.teaching_applies() || !self.apply_form() {
            return;
        }
        let generation = self.app.status().generation;
        let traced = self
            .app
            .optimizer()
            .and_then(|o| o.generation_trace())
            .map(|t| t.generation);
        let step = self.teaching.stepper.next_phase(generation, traced);
        self.teaching_step(step);
    }

    fn teach_next_generation(&mut self) {
        if !self.teaching_applies() || !self.apply_form() {
            return;
        }
        let generation = self.app.status().generation;
        let step = self.teaching.stepper.next_generation(generation);
        self.teaching_step(step);
    }

    /// The teaching view's part of a frame: arrivals, slow-motion play, caption, phase list and
    /// the OAX panel.
    pub(super) fn teaching_frame(&mut self, now: f64) {
        let on = is_on();
        dom::set_visible("teaching", on);
        if !on {
            return;
        }
        for id in ["teach-phase", "teach-generation", "teach-play"] {
            if let Ok(b) = by_id::<HtmlButtonElement>(id) {
                b.set_disabled(!self.teaching_applies());
            }
        }
        if !self.teaching_applies() {
            dom::set_text(
                "teach-caption",
                "The teaching view follows NSGA-II: choose NSGA-II as the method.",
            );
            return;
        }
        let status = self.app.status();
        if self.app.reproduction().is_none() {
            if self.teaching.stepper.waiting.is_some() && status.done {
                // The run ended before the generation asked for.
                self.teaching.stepper.waiting = None;
                self.teaching.playing = false;
            }
            self.teaching.stepper.arrived(status.generation);
        }
        if self.teaching.playing
            && self.teaching.stepper.waiting.is_none()
            && now - self.teaching.last_auto_ms >= seconds_per_phase() * 1000.0
        {
            self.teaching.last_auto_ms = now;
            if status.done && self.teaching.stepper.shown == Some(Phase::Survival) {
                self.teaching.playing = false;
            } else {
                self.teach_next_phase();
            }
        }
        dom::set_text(
            "teach-play",
            if self.teaching.playing {
                "Pause"
            } else {
                "Play"
            },
        );
        let shown = self.teaching.stepper.shown;
        let waiting = self.teaching.stepper.waiting;
        if let Ok(list) = by_id::<web_sys::Element>("teach-phases")
            && let Ok(items) = list.query_selector_all("li")
        {
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
        let traced = self
            .app
            .optimizer()
            .is_some_and(|o| o.generation_trace().is_some());
        let caption = match (waiting, traced, shown) {
            (Some((g, _)), _, _) => format!("Computing generation {g}…"),
            (None, true, Some(_)) => self
                .teaching_scene()
                .map_or(String::new(), |s| s.caption.clone()),
            (None, true, None) => {
                "Press “Next phase” to see the last generation's selection.".into()
            }
            (None, false, _) => "Press “Next phase” to make the first generation and see it \
                                 phase by phase (the initial population is made first)."
                .into(),
        };
        dom::set_text("teach-caption", &caption);
        // The OAX panel, redrawn when a new generation's crossover is there.
        let generation = status.generation;
        if self.teaching.oax_drawn != Some(generation) && self.app.reproduction().is_none() {
            self.teaching.oax_drawn = Some(generation);
            let hf = self.app.surface().heightfield.clone();
            oax_panel::show(self.app.optimizer().and_then(|o| o.last_crossover()), &hf);
        }
    }

    /// The scene of the shown phase of the last traced generation, built when either changed.
    fn teaching_scene(&mut self) -> Option<&TeachingScene> {
        let phase = self.teaching.stepper.shown?;
        let trace = self.app.optimizer()?.generation_trace()?;
        let key = (trace.generation, phase);
        if self.teaching.built != Some(key) {
            let p = &self.app.config().params;
            self.teaching.scene = Some(scene(trace, phase, p.crossover, p.crossover_probability));
            self.teaching.built = Some(key);
        }
        self.teaching.scene.as_ref()
    }

    /// Draws the teaching plot when the view is on and has a phase to show, and returns its
    /// layout; `None` otherwise (the ordinary plot is drawn).
    pub(super) fn draw_teaching_plot(
        &mut self,
        ctx: &CanvasRenderingContext2d,
        width: f64,
        height: f64,
        z_unit: &str,
    ) -> Option<Layout> {
        if !is_on() || !self.teaching_applies() {
            return None;
        }
        let hovered = self.teaching.hovered;
        let scene = self.teaching_scene()?;
        let layout = Layout::fit_scaled(
            width,
            height,
            scene.marks.iter().map(|m| &m.point),
            dom::checked("plot-log-e"),
        );
        let empty: [PlotPoint; 0] = [];
        plot::draw(
            ctx,
            &layout,
            &Scene {
                population: &[],
                front: &empty,
                selected: None,
                hovered: None,
                z_unit,
            },
        );
        plot::draw_marks(ctx, &layout, &scene.marks, &scene.legend, hovered);
        Some(layout)
    }

    /// Hover over the teaching plot: the read-out under the plot. True when the teaching plot
    /// is shown (the ordinary hover then does nothing).
    pub(super) fn teaching_hover(&mut self, layout: &Layout, x: f64, y: f64) -> bool {
        if !is_on() || self.teaching.built.is_none() || self.teaching.stepper.shown.is_none() {
            return false;
        }
        let marks = self
            .teaching
            .scene
            .as_ref()
            .map_or(&[][..], |s| s.marks.as_slice());
        let hovered = plot::hit_test_marks(layout, marks, x, y, HIT_RADIUS);
        let text = hovered
            .and_then(|i| marks.get(i))
            .map_or(String::new(), |m| m.label.clone());
        self.teaching.hovered = hovered;
        dom::set_text("teach-hover", &text);
        true
    }

    /// Shows mesh `k` of the OAX panel (see [`oax_panel::meshes`]) in the 3-D view.
    fn show_oax_mesh(&mut self, k: usize) {
        let Some(record) = self.app.optimizer().and_then(|o| o.last_crossover()) else {
            return;
        };
        if let Some(m) = oax_panel::meshes(record).into_iter().nth(k) {
            self.app.show_solution(m);
            self.update_layers();
        }
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
        }
    })?;
    on("teach-phase", "click", |ui| {
        ui.teaching.playing = false;
        ui.teach_next_phase();
    })?;
    on("teach-generation", "click", |ui| {
        ui.teaching.playing = false;
        ui.teach_next_generation();
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
            u.borrow_mut().show_oax_mesh(k);
        }
    });
    Ok(())
}
