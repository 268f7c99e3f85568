//! The glue between the page and the app: the exported [`WebApp`] the JS drives, event
//! listeners, the per-frame update (optimise within the budget, redraw the plot, redraw the 3-D
//! view when it changed), loading files, exports and the panic hook.

use super::app::{App, RunConfig, ShownMesh, Surface, shown_mesh};
use super::dom::{self, by_id, listen};
use super::export::{WorldMesh, front_csv};
use super::loader;
use super::plot::{self, Layout, PlotPoint, Scene};
use super::render::camera::OrbitCamera;
use super::render::geometry::{self, ViewMapping};
use super::render::gpu::{Renderer, Style};
use super::share::{FileFingerprint, ImportChoice, ShareLink, ViewToggles};
use super::share_view::{self, Origin};
use super::teaching_view::{self, TeachingUi};
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;
use web_sys::{HtmlCanvasElement, KeyboardEvent, MouseEvent, PointerEvent, WheelEvent};

mod compare_view;

/// Largest grid drawn with the full wireframe when nothing is selected (denser grids turn grey).
const MAX_WIREFRAME_POINTS: usize = 128 * 128;
/// Hover and click radius in the plot, CSS pixels.
const HIT_RADIUS: f64 = 8.0;

/// What the current layers were built from; a change rebuilds them.
#[derive(Clone, Debug, PartialEq)]
struct ViewKey {
    surface: usize,
    selected: Option<(usize, u64)>,
    toggles: ViewToggles,
}

/// The page's state: the app plus what only the page has (view, plot, pointers, links).
pub(super) struct Ui {
    pub(super) app: App,
    renderer: Option<Renderer>,
    pub(super) camera: OrbitCamera,
    view_key: Option<ViewKey>,
    shown: Option<ShownMesh>,
    pub(super) redraw: bool,
    plot_layout: Layout,
    front_points: Vec<PlotPoint>,
    pub(super) hovered: Option<usize>,
    pointers: Vec<(i32, f64, f64)>,
    painted: bool,
    /// Where the surface came from, for share links.
    pub(super) origin: Origin,
    /// A share link waiting for the user to drop the file it names.
    pub(super) waiting_for: Option<ShareLink>,
    /// The teaching view's state.
    pub(super) teaching: TeachingUi,
    /// Compare mode's state.
    compare: compare_view::CompareView,
}

fn performance_now() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or(0.0, |p| p.now())
}

fn z_unit(hf: &crate::heightfield::Heightfield) -> String {
    hf.source()
        .split("; ")
        .find_map(|part| part.strip_prefix("units: "))
        .unwrap_or("")
        .to_string()
}

impl Ui {
    /// The view toggles as the checkboxes say.
    pub(super) fn toggles(&self) -> ViewToggles {
        ViewToggles {
            original: dom::checked("show-original"),
            error: dom::checked("show-error"),
            kept: dom::checked("show-kept"),
        }
    }

    /// Ticks the checkboxes as `toggles` says.
    pub(super) fn set_toggles(&mut self, toggles: ViewToggles) {
        for (id, on) in [
            ("show-original", toggles.original),
            ("show-error", toggles.error),
            ("show-kept", toggles.kept),
        ] {
            if let Ok(input) = by_id::<web_sys::HtmlInputElement>(id) {
                input.set_checked(on);
            }
        }
    }

    pub(super) fn surface_info(&self) {
        let s = self.app.surface();
        let hf = &s.heightfield;
        dom::set_text(
            "surface-info",
            &format!(
                "{} · {}×{} grid · {} points · full mesh {} triangles",
                s.name,
                hf.width(),
                hf.height(),
                hf.len(),
                hf.full_triangles()
            ),
        );
        dom::set_text("surface-source", hf.source());
    }

    /// Rebuilds the 3-D layers when the selection, the surface or a toggle changed.
    pub(super) fn update_layers(&mut self) {
        let toggles = self.toggles();
        let hf = self.app.surface().heightfield.clone();
        let key = ViewKey {
            surface: Arc::as_ptr(&hf) as usize,
            selected: self.app.selected().map(|s| (s.t, s.e_sum.to_bits())),
            toggles,
        };
        if self.view_key.as_ref() == Some(&key) {
            return;
        }
        let selection_changed = self
            .view_key
            .as_ref()
            .is_none_or(|k| k.surface != key.surface || k.selected != key.selected);
        if selection_changed {
            self.shown = match self.app.selected() {
                Some(s) => match shown_mesh(&hf, &s.kept) {
                    Ok(m) => Some(m),
                    Err(e) => {
                        dom::show_load_message(&format!("cannot show this mesh: {e}"), true);
                        None
                    }
                },
                None => None,
            };
            self.selection_info();
        }
        self.view_key = Some(key);
        let map = ViewMapping::new(&hf);
        let surface_colour = [0.80, 0.72, 0.58, 1.0];
        let wire_colour = [0.12, 0.12, 0.16, 1.0];
        let mut layers = Vec::new();
        match &self.shown {
            Some(mesh) => {
                let max_error = mesh.point_error.iter().cloned().fold(0.0, f64::max);
                if toggles.error {
                    let err = &mesh.point_error;
                    let scale = if max_error > 0.0 {
                        1.0 / max_error
                    } else {
                        0.0
                    };
                    layers.push((
                        Style::Fill,
                        geometry::grid_surface(&hf, &map, &|i| {
                            geometry::error_colour(err[i] * scale)
                        }),
                    ));
                } else {
                    layers.push((
                        Style::Fill,
                        geometry::flat_mesh(&hf, &map, &mesh.triangles, surface_colour),
                    ));
                }
                layers.push((
                    Style::Lines,
                    geometry::wireframe(&hf, &map, &mesh.triangles, wire_colour),
                ));
                if toggles.original {
                    layers.push((
                        Style::Translucent,
                        geometry::grid_surface(&hf, &map, &|_| [0.25, 0.45, 0.85, 0.35]),
                    ));
                }
                if toggles.kept {
                    layers.push((
                        Style::Fill,
                        geometry::markers(
                            &hf,
                            &map,
                            &mesh.kept,
                            map.step() * 1.2,
                            [0.85, 0.1, 0.1, 1.0],
                        ),
                    ));
                }
                dom::set_text("legend-max", &plot::format_value(max_error));
                dom::set_visible("legend", toggles.error);
            }
            None => {
                // Nothing selected: the full-resolution surface.
                layers.push((
                    Style::Fill,
                    geometry::grid_surface(&hf, &map, &|_| surface_colour),
                ));
                if hf.len() <= MAX_WIREFRAME_POINTS {
                    let w = hf.width() as u32;
                    let mut tris = Vec::with_capacity(hf.full_triangles());
                    for y in 0..hf.height() as u32 - 1 {
                        for x in 0..w - 1 {
                            let a = y * w + x;
                            tris.push([a, a + 1, a + w]);
                            tris.push([a + 1, a + w + 1, a + w]);
                        }
                    }
                    layers.push((
                        Style::Lines,
                        geometry::wireframe(&hf, &map, &tris, [0.35, 0.30, 0.25, 1.0]),
                    ));
                }
                dom::set_visible("legend", false);
            }
        }
        if let Some(r) = self.renderer.as_mut() {
            r.set_layers(layers);
        }
        self.redraw = true;
    }

    fn selection_info(&self) {
        let text = match (self.app.selected(), &self.shown) {
            (Some(s), Some(m)) => format!(
                "selected: T = {} triangles · {} vertices · E = {} · E_max = {}",
                s.t,
                m.kept.len(),
                plot::format_value(s.e_sum),
                plot::format_value(s.e_max)
            ),
            _ => "selected: none (showing the full-resolution surface); click a point of the front"
                .to_string(),
        };
        dom::set_text("selection-info", &text);
        if let Ok(e) = by_id::<web_sys::Element>("selection-info") {
            let _ = e.set_attribute(
                "data-vertices",
                &self
                    .shown
                    .as_ref()
                    .map_or(String::new(), |m| m.kept.len().to_string()),
            );
        }
    }

    fn draw_plot(&mut self) {
        let Some((ctx, cw, ch)) = dom::canvas_2d("plot") else {
            return;
        };
        let unit = z_unit(&self.app.surface().heightfield);
        if let Some(layout) = self.draw_teaching_plot(&ctx, cw, ch, &unit) {
            self.plot_layout = layout;
            self.front_points.clear();
            return;
        }
        self.front_points = self
            .app
            .front()
            .map(|f| {
                f.solutions()
                    .iter()
                    .map(|s| PlotPoint {
                        t: s.t as f64,
                        e: s.e_sum,
                    })
                    .collect()
            })
            .unwrap_or_default();
        let population: Vec<(PlotPoint, usize)> = self
            .app
            .optimizer()
            .map(|o| {
                o.population_points()
                    .into_iter()
                    .map(|(t, e, rank)| (PlotPoint { t, e }, rank))
                    .collect()
            })
            .unwrap_or_default();
        self.plot_layout = Layout::fit_scaled(
            cw,
            ch,
            self.front_points
                .iter()
                .chain(population.iter().map(|(p, _)| p)),
            dom::checked("plot-log-e"),
        );
        plot::draw(
            &ctx,
            &self.plot_layout,
            &Scene {
                population: &population,
                front: &self.front_points,
                selected: self.app.selected_front_index(),
                hovered: self.hovered,
                z_unit: &unit,
            },
        );
    }

    fn resize_view(&mut self) {
        let Ok(canvas) = by_id::<HtmlCanvasElement>("view") else {
            return;
        };
        let dpr = web_sys::window().map_or(1.0, |w| w.device_pixel_ratio());
        let w = ((canvas.client_width() as f64) * dpr).round().max(1.0) as u32;
        let h = ((canvas.client_height() as f64) * dpr).round().max(1.0) as u32;
        if canvas.width() != w || canvas.height() != h {
            canvas.set_width(w);
            canvas.set_height(h);
            if let Some(r) = self.renderer.as_mut() {
                r.resize(w, h);
            }
            self.redraw = true;
        }
    }

    fn frame(&mut self, _now: f64) {
        let budget = self.app.config().budget_ms;
        let mut clock = performance_now;
        self.app.tick(budget, &mut clock);
        self.compare_frame();
        let mut status = dom::status_text(&self.app.status(), self.app.is_running());
        if let Some(r) = self.app.reproduction() {
            status.push_str(&format!(
                " · re-running the shared run to generation {}",
                r.generations
            ));
        }
        dom::set_text("status", &status);
        self.teaching_frame(performance_now());
        self.update_layers();
        self.draw_plot();
        self.resize_view();
        if self.redraw
            && let Some(r) = self.renderer.as_mut()
        {
            r.draw(&self.camera);
            self.redraw = false;
            if !self.painted {
                // Lets anyone (the end-to-end test, DevTools) read the time to first paint.
                self.painted = true;
                if let Some(p) = web_sys::window().and_then(|w| w.performance()) {
                    let _ = p.mark("paretomesh-first-paint");
                }
            }
        }
    }

    pub(super) fn apply_form(&mut self) -> bool {
        match dom::read_config() {
            Ok(config) => {
                // The GA parameters mean nothing to the classical methods: hide them.
                let genetic = config.algorithm.is_genetic();
                for id in [
                    "population",
                    "generations",
                    "crossover",
                    "crossover-probability",
                    "mutation-probability",
                    "seed",
                ] {
                    if let Some(label) = dom::document()
                        .get_element_by_id(id)
                        .and_then(|e| e.parent_element())
                        .and_then(|e| e.dyn_into::<web_sys::HtmlElement>().ok())
                    {
                        label.set_hidden(!genetic);
                    }
                }
                self.app.set_config(config);
                dom::set_text("run-message", "");
                true
            }
            Err(e) => {
                dom::set_text("run-message", &e);
                false
            }
        }
    }

    /// Shows a parsed file whose bytes have `fingerprint`; when a share link waits for a file,
    /// only that file is accepted and the link's run follows.
    fn load(
        &mut self,
        fingerprint: FileFingerprint,
        parsed: Result<crate::heightfield::Heightfield, String>,
    ) -> bool {
        let name = fingerprint.name.clone();
        match parsed {
            Ok(hf) => {
                let link = match self.check_awaited_file(&fingerprint) {
                    Ok(link) => link,
                    Err(e) => {
                        dom::show_load_message(&e, true);
                        return false;
                    }
                };
                self.set_surface(&name, hf, Origin::File(fingerprint));
                dom::show_load_message(&format!("loaded {name}"), false);
                if let Some(link) = link {
                    self.apply_run(&link);
                }
                true
            }
            Err(e) => {
                // The previous surface and its run stay as they were.
                dom::show_load_message(&e, true);
                false
            }
        }
    }

    fn export(&mut self, kind: &str) -> Result<(), String> {
        let s = self.app.surface();
        let hf = s.heightfield.clone();
        let stem = s
            .name
            .rsplit_once('.')
            .map_or(s.name.as_str(), |(a, _)| a)
            .to_string();
        match kind {
            "json" => {
                let front = self
                    .app
                    .front()
                    .ok_or("run an algorithm first: the front is empty")?;
                let config = self.app.config();
                let status = self.app.status();
                let file = crate::run_file::RunFile::new(
                    &mut crate::evaluator::Evaluator::new(hf.clone()),
                    config.algorithm.key(),
                    super::algorithms::params_json(config.algorithm, &config.params),
                    config.params.seed,
                    status.evaluations,
                    status.elapsed_ms.round() as u64,
                    front,
                )
                .map_err(|e| e.to_string())?;
                let json = serde_json::to_string_pretty(&file).map_err(|e| e.to_string())?;
                dom::download(
                    &format!("{stem}_front.json"),
                    "application/json",
                    json.as_bytes(),
                )
            }
            "csv" => {
                let front = self
                    .app
                    .front()
                    .ok_or("run an algorithm first: the front is empty")?;
                dom::download(
                    &format!("{stem}_front.csv"),
                    "text/csv",
                    front_csv(front).as_bytes(),
                )
            }
            _ => {
                let mesh = match &self.shown {
                    Some(m) => m.clone(),
                    None => shown_mesh(&hf, &self.app.shown_kept())?,
                };
                let world = WorldMesh::new(&hf, &mesh.kept, &mesh.triangles)?;
                let note = format!(
                    "ParetoMesh simplification of {}: {} vertices, {} triangles, E = {}",
                    s.name,
                    mesh.kept.len(),
                    mesh.triangles.len(),
                    mesh.e_sum
                );
                let name = format!("{stem}_{}t.{kind}", mesh.triangles.len());
                match kind {
                    "ply" => dom::download(
                        &name,
                        "application/octet-stream",
                        world.to_ply(&note).as_bytes(),
                    ),
                    "obj" => dom::download(&name, "text/plain", world.to_obj(&note).as_bytes()),
                    "stl" => dom::download(&name, "application/octet-stream", &world.to_stl(&note)),
                    _ => Err(format!("unknown export kind {kind}")),
                }
            }
        }
    }
}

/// Calls `f` on the page state whenever element `id` fires `event`. Fails when the page lacks
/// the element.
pub(super) fn on_event(
    ui: &Rc<RefCell<Ui>>,
    id: &str,
    event: &str,
    f: impl Fn(&mut Ui) + 'static,
) -> Result<(), String> {
    let ui = ui.clone();
    let target: web_sys::EventTarget = by_id(id)?;
    listen(&target, event, move |_: web_sys::Event| {
        f(&mut ui.borrow_mut())
    });
    Ok(())
}

/// The app as the page's JS sees it.
#[wasm_bindgen]
pub struct WebApp {
    ui: Rc<RefCell<Ui>>,
}

fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let message = info.to_string();
        web_sys::console::error_1(&format!("ParetoMesh panicked: {message}").into());
        dom::set_text("panic-message", &message);
        dom::set_visible("panic", true);
    }));
}

/// Starts the app: panic hook, built-in surface, wgpu on the `#view` canvas (WebGL2 only when
/// `force_webgl`), listeners. The surface is drawn on the first [`WebApp::frame`].
#[wasm_bindgen]
pub async fn start(force_webgl: bool) -> Result<WebApp, JsValue> {
    install_panic_hook();
    let hf = loader::builtin();
    let mut ui = Ui {
        app: App::new(
            Surface {
                name: loader::BUILTIN_NAME.to_string(),
                heightfield: Arc::new(hf),
            },
            RunConfig::default(),
        ),
        renderer: None,
        camera: OrbitCamera::default(),
        view_key: None,
        shown: None,
        redraw: true,
        plot_layout: Layout::fit(1.0, 1.0, []),
        front_points: Vec::new(),
        hovered: None,
        pointers: Vec::new(),
        painted: false,
        origin: Origin::Builtin(loader::BUILTIN_NAME),
        waiting_for: None,
        teaching: TeachingUi::default(),
        compare: Default::default(),
    };
    teaching_view::fill().map_err(|e| JsValue::from_str(&e))?;
    share_view::fill_menus(&ui.app).map_err(|e| JsValue::from_str(&e))?;
    ui.update_share_controls();
    dom::write_config(ui.app.config()).map_err(|e| JsValue::from_str(&e))?;
    ui.surface_info();
    by_id::<web_sys::HtmlElement>("legend-bar")
        .map_err(|e| JsValue::from_str(&e))?
        .style()
        .set_property("background", &geometry::error_legend_css())?;
    let canvas = by_id::<HtmlCanvasElement>("view").map_err(|e| JsValue::from_str(&e))?;
    let dpr = web_sys::window().map_or(1.0, |w| w.device_pixel_ratio());
    canvas.set_width(((canvas.client_width() as f64) * dpr).round().max(1.0) as u32);
    canvas.set_height(((canvas.client_height() as f64) * dpr).round().max(1.0) as u32);
    match Renderer::new(canvas.clone(), force_webgl).await {
        Ok(r) => {
            dom::set_text("backend", r.backend);
            ui.renderer = Some(r);
        }
        Err(e) => dom::set_text("backend", &format!("no 3-D view: {e}")),
    }
    ui.selection_info();
    let app = WebApp {
        ui: Rc::new(RefCell::new(ui)),
    };
    app.wire(&canvas).map_err(|e| JsValue::from_str(&e))?;
    share_view::wire(&app.ui).map_err(|e| JsValue::from_str(&e))?;
    teaching_view::wire(&app.ui).map_err(|e| JsValue::from_str(&e))?;
    Ok(app)
}

#[wasm_bindgen]
impl WebApp {
    /// One animation frame: optimise within the budget, update the status, plot and view.
    pub fn frame(&self, now: f64) {
        self.ui.borrow_mut().frame(now);
    }

    /// Loads a dropped or picked file (`sidecar` for a .f32 grid). On failure the message shows
    /// next to the drop zone and the current surface stays. Returns whether it loaded.
    #[wasm_bindgen(js_name = loadFile)]
    pub fn load_file(&self, name: &str, bytes: &[u8], sidecar: Option<Vec<u8>>) -> bool {
        let parsed = loader::parse(
            name,
            bytes,
            sidecar.as_deref(),
            &crate::heightfield::ImportOptions::default(),
        );
        let fingerprint = FileFingerprint {
            import: import_choice(&parsed, None),
            ..FileFingerprint::of(name, bytes)
        };
        self.ui.borrow_mut().load(fingerprint, parsed)
    }

    /// Shows a surface the Worker parsed (see [`super::transfer`]) from a file of `size` bytes
    /// whose FNV-1a hash is `hash` (16 hex digits, from [`fnv1a64_hex`], which the Worker runs
    /// on the file's bytes); like [`WebApp::load_file`] otherwise. `projection` is the import
    /// dialog's projection for a mesh that had to be resampled ("auto" when absent): with the
    /// grid's size it goes into share links of this surface.
    #[wasm_bindgen(js_name = loadParsed)]
    pub fn load_parsed(
        &self,
        name: &str,
        parsed: JsValue,
        size: f64,
        hash: &str,
        projection: Option<String>,
    ) -> bool {
        let parsed = super::transfer::surface_from_js(&parsed).map_err(|e| format!("{name}: {e}"));
        let fingerprint = FileFingerprint {
            name: name.to_string(),
            size: size as u64,
            fnv1a64: u64::from_str_radix(hash, 16).unwrap_or(0),
            import: import_choice(&parsed, projection),
        };
        self.ui.borrow_mut().load(fingerprint, parsed)
    }

    /// The import choice (`{projection, width, height}`) of the file a share link waits for,
    /// or null: the page then re-parses a dropped mesh that way instead of asking.
    #[wasm_bindgen(js_name = pendingImport)]
    pub fn pending_import(&self) -> JsValue {
        self.ui
            .borrow()
            .awaited_import()
            .and_then(|choice| serde_wasm_bindgen::to_value(&choice).ok())
            .unwrap_or(JsValue::NULL)
    }

    /// Opens a share link (the URL hash, with or without `#`); see [`super::share_view`].
    #[wasm_bindgen(js_name = openLink)]
    pub fn open_link(&self, hash: &str) {
        self.ui.borrow_mut().open_link(hash);
    }

    /// The archive front as flat `[T0, E0, T1, E1, …]` (increasing T), for tests and the
    /// console.
    #[wasm_bindgen(js_name = frontObjectives)]
    pub fn front_objectives(&self) -> Vec<f64> {
        let ui = self.ui.borrow();
        ui.app.front().map_or_else(Vec::new, |f| {
            f.solutions()
                .iter()
                .flat_map(|s| [s.t as f64, s.e_sum])
                .collect()
        })
    }

    /// The selected solution as `[front index or −1, T, E_sum]`, if any.
    #[wasm_bindgen(js_name = selectedObjectives)]
    pub fn selected_objectives(&self) -> Option<Vec<f64>> {
        let ui = self.ui.borrow();
        let s = ui.app.selected()?;
        let index = ui.app.selected_front_index().map_or(-1.0, |i| i as f64);
        Some(vec![index, s.t as f64, s.e_sum])
    }

    /// True while a share link's run is being re-done.
    #[wasm_bindgen(js_name = isReproducing)]
    pub fn is_reproducing(&self) -> bool {
        self.ui.borrow().app.reproduction().is_some()
    }

    /// Generations completed by the current run.
    pub fn generation(&self) -> f64 {
        self.ui.borrow().app.status().generation as f64
    }

    /// The teaching view's shown phase (its label) and the generation of its trace, if any.
    #[wasm_bindgen(js_name = teachingState)]
    pub fn teaching_state(&self) -> Option<Vec<String>> {
        let ui = self.ui.borrow();
        let phase = ui.teaching_phase()?;
        let generation = ui
            .app
            .optimizer()
            .and_then(|o| o.generation_trace())
            .map_or(0, |t| t.generation);
        Some(vec![phase.label().to_string(), generation.to_string()])
    }
}

/// FNV-1a hash of `bytes` as 16 hex digits: the fingerprint a share link gives a user's file.
#[wasm_bindgen(js_name = fnv1a64Hex)]
pub fn fnv1a64_hex(bytes: &[u8]) -> String {
    format!("{:016x}", super::share::fnv1a64(bytes))
}

#[wasm_bindgen]
impl WebApp {
    /// Shows a loading message (`error` styles it as an error), for the JS file reader.
    #[wasm_bindgen(js_name = showLoadMessage)]
    pub fn show_load_message(&self, text: &str, error: bool) {
        dom::show_load_message(text, error);
    }

    /// Number of members of the archive front.
    #[wasm_bindgen(js_name = frontLength)]
    pub fn front_length(&self) -> usize {
        self.ui.borrow().app.front().map_or(0, |f| f.len())
    }

    /// CSS-pixel position in the `#plot` canvas of front member `index` as of the last frame.
    #[wasm_bindgen(js_name = frontPointPosition)]
    pub fn front_point_position(&self, index: usize) -> Option<Vec<f64>> {
        let ui = self.ui.borrow();
        let p = ui.front_points.get(index)?;
        let (x, y) = ui.plot_layout.to_pixel(*p);
        Some(vec![x, y])
    }

    /// Vertices of the selected mesh (kept points, corners included), if one is selected.
    #[wasm_bindgen(js_name = selectedVertexCount)]
    pub fn selected_vertex_count(&self) -> Option<usize> {
        self.ui.borrow().shown.as_ref().map(|m| m.kept.len())
    }

    /// Name of the loaded surface.
    #[wasm_bindgen(js_name = surfaceName)]
    pub fn surface_name(&self) -> String {
        self.ui.borrow().app.surface().name.clone()
    }
}

impl WebApp {
    fn wire(&self, canvas: &HtmlCanvasElement) -> Result<(), String> {
        let on = |id: &str, event: &str, f: Box<dyn Fn(&mut Ui)>| on_event(&self.ui, id, event, f);
        on(
            "run",
            "click",
            Box::new(|ui| {
                if ui.apply_form()
                    && let Err(e) = ui.app.run()
                {
                    dom::set_text("run-message", &e);
                }
            }),
        )?;
        on("pause", "click", Box::new(|ui| ui.app.pause()))?;
        on(
            "step",
            "click",
            Box::new(|ui| {
                if ui.apply_form()
                    && let Err(e) = ui.app.step_once()
                {
                    dom::set_text("run-message", &e);
                }
            }),
        )?;
        on(
            "reset",
            "click",
            Box::new(|ui| {
                ui.app.reset();
                ui.apply_form();
            }),
        )?;
        for id in [
            "algorithm",
            "population",
            "generations",
            "crossover",
            "crossover-probability",
            "mutation-probability",
            "seed",
            "budget",
        ] {
            on(
                id,
                "change",
                Box::new(|ui| {
                    ui.apply_form();
                }),
            )?;
        }
        for id in ["show-original", "show-error", "show-kept"] {
            on(id, "change", Box::new(|ui| ui.update_layers()))?;
        }
        on(
            "reset-view",
            "click",
            Box::new(|ui| {
                ui.camera = OrbitCamera::default();
                ui.redraw = true;
            }),
        )?;
        for kind in ["ply", "obj", "stl", "csv", "json"] {
            on(
                &format!("export-{kind}"),
                "click",
                Box::new(move |ui| {
                    if let Err(e) = ui.export(kind) {
                        dom::set_text("export-message", &e);
                    } else {
                        dom::set_text("export-message", "");
                    }
                }),
            )?;
        }
        // The plot: hover, click, arrow keys.
        let plot: HtmlCanvasElement = by_id("plot")?;
        let ui = self.ui.clone();
        listen(&plot, "mousemove", move |e: MouseEvent| {
            let mut ui = ui.borrow_mut();
            let (x, y) = (e.offset_x() as f64, e.offset_y() as f64);
            let layout = ui.plot_layout;
            if ui.teaching_hover(&layout, x, y) {
                return;
            }
            ui.hovered = plot::hit_test(&ui.plot_layout, &ui.front_points, x, y, HIT_RADIUS);
        });
        let ui = self.ui.clone();
        listen(&plot, "mouseleave", move |_: MouseEvent| {
            ui.borrow_mut().hovered = None
        });
        let ui = self.ui.clone();
        listen(&plot, "click", move |e: MouseEvent| {
            let mut ui = ui.borrow_mut();
            let (x, y) = (e.offset_x() as f64, e.offset_y() as f64);
            if let Some(i) = plot::hit_test(&ui.plot_layout, &ui.front_points, x, y, HIT_RADIUS) {
                ui.app.select_front_index(Some(i));
                ui.update_layers();
            }
        });
        let ui = self.ui.clone();
        listen(&plot, "keydown", move |e: KeyboardEvent| {
            let delta = match e.key().as_str() {
                "ArrowRight" | "ArrowUp" => 1,
                "ArrowLeft" | "ArrowDown" => -1,
                _ => return,
            };
            e.prevent_default();
            let mut ui = ui.borrow_mut();
            ui.app.move_selection(delta);
            ui.update_layers();
        });
        // The 3-D view: one pointer orbits (pans with the right button or Shift), two pinch.
        let ui = self.ui.clone();
        let c = canvas.clone();
        listen(canvas, "pointerdown", move |e: PointerEvent| {
            let _ = c.set_pointer_capture(e.pointer_id());
            let mut ui = ui.borrow_mut();
            ui.pointers.retain(|p| p.0 != e.pointer_id());
            ui.pointers
                .push((e.pointer_id(), e.client_x() as f64, e.client_y() as f64));
        });
        let ui = self.ui.clone();
        let c = canvas.clone();
        listen(canvas, "pointermove", move |e: PointerEvent| {
            let mut ui = ui.borrow_mut();
            let Some(k) = ui.pointers.iter().position(|p| p.0 == e.pointer_id()) else {
                return;
            };
            let (x, y) = (e.client_x() as f64, e.client_y() as f64);
            let (_, px, py) = ui.pointers[k];
            let (dx, dy) = ((x - px) as f32, (y - py) as f32);
            let height = c.client_height() as f32;
            if ui.pointers.len() >= 2 {
                let other = ui.pointers[1 - k.min(1)];
                let before = ((px - other.1).powi(2) + (py - other.2).powi(2)).sqrt();
                let after = ((x - other.1).powi(2) + (y - other.2).powi(2)).sqrt();
                if before > 0.0 && after > 0.0 {
                    ui.camera.zoom((before / after) as f32);
                }
                ui.camera.pan(dx / 2.0, dy / 2.0, height);
            } else if e.buttons() & 2 != 0 || e.buttons() & 4 != 0 || e.shift_key() {
                ui.camera.pan(dx, dy, height);
            } else {
                ui.camera.orbit(dx, dy);
            }
            ui.pointers[k] = (e.pointer_id(), x, y);
            ui.redraw = true;
        });
        for event in ["pointerup", "pointercancel"] {
            let ui = self.ui.clone();
            listen(canvas, event, move |e: PointerEvent| {
                ui.borrow_mut().pointers.retain(|p| p.0 != e.pointer_id());
            });
        }
        let ui = self.ui.clone();
        listen(canvas, "wheel", move |e: WheelEvent| {
            e.prevent_default();
            let mut ui = ui.borrow_mut();
            ui.camera.zoom((e.delta_y() * 0.0015).exp() as f32);
            ui.redraw = true;
        });
        listen(canvas, "contextmenu", |e: MouseEvent| e.prevent_default());
        compare_view::wire(&self.ui)?;
        Ok(())
    }
}

/// How a parsed file became a grid, for its share links: `None` for a file that is a grid, else
/// the projection chosen (`"auto"` when none was) and the grid size it gave.
fn import_choice(
    parsed: &Result<crate::heightfield::Heightfield, String>,
    projection: Option<String>,
) -> Option<ImportChoice> {
    let hf = parsed.as_ref().ok().filter(|hf| hf.resampled())?;
    Some(ImportChoice {
        projection: projection.unwrap_or_else(|| "auto".to_string()),
        width: hf.width() as u32,
        height: hf.height() as u32,
    })
}
