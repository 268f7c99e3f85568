//! The page's state, `Ui`: the app plus what only the page has (3-D view, plot, pointers,
//! share-link origin, the teaching and compare panels), with the steps every view shares:
//! reading the form, the view toggles, the surface and selection lines, and the 3-D layers.

use super::dom::{self, by_id, listen};
use super::gpu::Renderer;
use super::style::Style;
use crate::app::algorithms::{self, Algorithm, Field};
use crate::app::camera::OrbitCamera;
use crate::app::compare::{self, CompareRun};
use crate::app::geometry::{self, Geometry, ViewMapping};
use crate::app::loader;
use crate::app::mesh_builds::MeshBuilds;
use crate::app::plot::{self, Layout, PlotPoint};
use crate::app::share::{Origin, ShareLink, ViewToggles};
use crate::app::state::{App, MAX_DRAWN_TRIANGLES, ShownMesh, shown_mesh};
use crate::app::teaching::{Stepper, TeachingScene};
use crate::evolution::trace::Phase;
use crate::heightfield::Heightfield;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use web_sys::HtmlCanvasElement;

/// Largest grid drawn with the full wireframe when nothing is selected (denser grids turn grey).
const MAX_WIREFRAME_POINTS: usize = 128 * 128;
/// Hover and click radius in the plot, CSS pixels.
pub(super) const HIT_RADIUS: f64 = 8.0;

/// What the current layers were built from; a change rebuilds them.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ViewKey {
    surface: usize,
    selected: Option<(usize, u64)>,
    toggles: ViewToggles,
}

/// What the plot shows: the app's revision, the pointer's and the selection's members, the
/// canvas size and the axes.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct PlotKey {
    pub(super) revision: u64,
    pub(super) hovered: Option<usize>,
    pub(super) selected: Option<usize>,
    pub(super) size: (f64, f64),
    pub(super) e_axis: crate::app::plot::EAxis,
    pub(super) log_e: bool,
}

/// The page's state: the app plus what only the page has (view, plot, pointers, links).
pub(super) struct Ui {
    /// The surface, the run and the selection.
    pub(super) app: App,
    /// The 3-D view, when the browser gave one.
    pub(super) renderer: Option<Renderer>,
    pub(super) camera: OrbitCamera,
    /// What the 3-D layers were last built from.
    pub(super) view_key: Option<ViewKey>,
    /// The selected mesh with its per-point errors, as the 3-D view shows it.
    pub(super) shown: Option<ShownMesh>,
    /// A tiled member's mesh being built in the mesh worker.
    pub(super) meshes: MeshBuilds,
    /// The 3-D view must be drawn again on the next frame.
    pub(super) redraw: bool,
    /// What the plot was last drawn from: it is drawn again only when that changes.
    pub(super) plot_key: Option<PlotKey>,
    /// The plot's layout and front points as of the last frame, for hit-testing.
    pub(super) plot_layout: Layout,
    pub(super) front_points: Vec<PlotPoint>,
    /// Index of the front member under the mouse.
    pub(super) hovered: Option<usize>,
    /// Pointers down on the 3-D view: (id, x, y) as last seen.
    pub(super) pointers: Vec<(i32, f64, f64)>,
    /// The first paint was marked.
    pub(super) painted: bool,
    /// Where the surface came from, for share links.
    pub(super) origin: Origin,
    /// A share link waiting for the user to drop the file it names.
    pub(super) waiting_for: Option<ShareLink>,
    /// The teaching view's state.
    pub(super) teaching: TeachingUi,
    /// Compare mode's state.
    pub(super) compare: CompareView,
}

/// The unit of z named in the surface's source note ("" when it names none).
pub(super) fn z_unit(hf: &Heightfield) -> String {
    hf.source()
        .split("; ")
        .find_map(|part| part.strip_prefix("units: "))
        .unwrap_or("")
        .to_string()
}

/// The teaching view's page state.
#[derive(Default)]
pub(super) struct TeachingUi {
    /// Which phase is shown and which generation is awaited.
    pub(super) stepper: Stepper,
    /// The shown phase's marks, legend and caption, built once per (generation, phase).
    pub(super) scene: Option<TeachingScene>,
    /// Index of the mark under the mouse.
    pub(super) hovered: Option<usize>,
    /// Slow-motion play is on.
    pub(super) playing: bool,
    /// When play last advanced a phase (ms, performance clock).
    pub(super) last_auto_ms: f64,
    /// The crossover generation the OAX panel was drawn for.
    pub(super) oax_drawn: Option<u64>,
    /// The (generation, phase) `scene` was built for.
    pub(super) built: Option<(u64, Phase)>,
}

/// The compare panel's state.
#[derive(Default)]
pub(super) struct CompareView {
    /// The comparison, once started.
    pub(super) run: Option<CompareRun>,
    /// The compare plot's layout as of the last frame, for hit-testing.
    pub(super) layout: Option<Layout>,
    /// Every plotted member: (method index, index in its front, position).
    pub(super) points: Vec<(usize, usize, PlotPoint)>,
    /// Index into `points` under the mouse.
    pub(super) hovered: Option<usize>,
}

impl Ui {
    /// The page state of `app` on a surface from `origin`, before the 3-D view exists.
    pub(super) fn new(app: App, origin: Origin) -> Self {
        Self {
            app,
            renderer: None,
            camera: OrbitCamera::default(),
            view_key: None,
            shown: None,
            meshes: MeshBuilds::default(),
            redraw: true,
            plot_key: None,
            plot_layout: Layout::fit(1.0, 1.0, []),
            front_points: Vec::new(),
            hovered: None,
            pointers: Vec::new(),
            painted: false,
            origin,
            waiting_for: None,
            teaching: TeachingUi::default(),
            compare: CompareView::default(),
        }
    }

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
        // A GeoTIFF's map frame stays in view: the exports' coordinates are map coordinates.
        let source = match loader::georeference_summary(hf) {
            Some(geo) => format!("{} · georeferencing: {geo}", hf.source()),
            None => hf.source().to_string(),
        };
        dom::set_text("surface-source", &source);
    }

    /// Rebuilds the 3-D layers when the selection, the surface or a toggle changed. A tiled
    /// member's mesh is asked of the mesh worker instead: the layers shown stay until it comes
    /// (see [`crate::app::mesh_builds`]).
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
        let surface_changed = self
            .view_key
            .as_ref()
            .is_none_or(|k| k.surface != key.surface);
        let selection_changed =
            surface_changed || self.view_key.as_ref().map(|k| k.selected) != Some(key.selected);
        self.view_key = Some(key);
        if surface_changed {
            self.meshes.cancel();
            self.meshes.grid_lost();
        }
        if selection_changed {
            if self.request_tiled_mesh() {
                self.selection_info();
                return;
            }
            self.meshes.cancel();
            self.refresh_shown();
        }
        self.build_layers();
    }

    /// Asks the mesh worker for the selection's mesh when it is a tiled run's member; returns
    /// whether it did.
    fn request_tiled_mesh(&mut self) -> bool {
        let request = super::costs::timed("mesh request", || {
            self.app.selected_tiled_parts(Some(MAX_DRAWN_TRIANGLES))
        });
        match request {
            Some(Ok((member, plan, parts))) => {
                self.meshes.request(member, plan, parts);
                true
            }
            // Nothing selected, an untiled run, or a member no longer on the front (which
            // the page's own rebuild reports).
            _ => false,
        }
    }

    /// Builds the 3-D layers of the shown mesh (or of the full surface) and hands them to the
    /// view.
    pub(super) fn build_layers(&mut self) {
        let toggles = self.toggles();
        let hf = self.app.surface().heightfield.clone();
        let map = ViewMapping::new(&hf);
        let (layers, max_error) = match &self.shown {
            Some(mesh) => {
                let max_error = mesh.point_error.iter().cloned().fold(0.0, f64::max);
                (
                    mesh_layers(&hf, &map, mesh, max_error, toggles),
                    Some(max_error),
                )
            }
            None => (full_surface_layers(&hf, &map), None),
        };
        self.set_layers(layers, max_error);
    }

    /// Hands `layers` to the view, with the error legend's top value `max_error` (`None`:
    /// no mesh, no legend).
    pub(super) fn set_layers(&mut self, layers: Vec<(Style, Geometry)>, max_error: Option<f64>) {
        match max_error {
            Some(max) => {
                dom::set_text("legend-max", &plot::format_value(max));
                dom::set_visible("legend", self.toggles().error);
            }
            None => dom::set_visible("legend", false),
        }
        if let Some(r) = self.renderer.as_mut() {
            super::costs::timed("layer upload", || r.set_layers(layers));
        }
        self.redraw = true;
    }

    /// Re-triangulates the selected solution for the view (or shows none); a member over
    /// [`MAX_DRAWN_TRIANGLES`] is drawn as a coarser member of the same front.
    fn refresh_shown(&mut self) {
        self.shown = self
            .app
            .selected_mesh(Some(MAX_DRAWN_TRIANGLES))
            .and_then(|m| match m {
                Ok(m) => Some(m),
                Err(e) => {
                    dom::show_load_message(&format!("cannot show this mesh: {e}"), true);
                    None
                }
            });
        self.selection_info();
    }

    pub(super) fn selection_info(&self) {
        let building = self.meshes.building();
        let text = match (self.app.selected(), &self.shown) {
            (Some(s), _) if building.is_some() => format!(
                "selected: T = {} triangles · E = {} · E_max = {} · building {}its mesh from \
                 the tiles in a Web Worker…",
                s.t,
                plot::format_value(s.e_sum),
                plot::format_value(s.e_max),
                match building {
                    Some(b) if b.t != s.t =>
                        format!("the member with T = {} that stands in for it: ", b.t),
                    _ => String::new(),
                }
            ),
            (Some(s), Some(m)) if m.triangles.len() != s.t => format!(
                "selected: T = {} triangles · E = {} · E_max = {} · drawn as the front's member \
                 with T = {} ({} vertices): the view draws at most {} triangles; exports \
                 write the selected mesh",
                s.t,
                plot::format_value(s.e_sum),
                plot::format_value(s.e_max),
                m.triangles.len(),
                m.kept.len(),
                MAX_DRAWN_TRIANGLES
            ),
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
                    .filter(|_| building.is_none())
                    .map_or(String::new(), |m| m.kept.len().to_string()),
            );
        }
    }

    pub(super) fn resize_view(&mut self) {
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

    /// Reads the parameter form into the app's configuration, or shows why it cannot.
    pub(super) fn apply_form(&mut self) -> bool {
        show_parameters();
        match dom::read_config() {
            Ok(config) => {
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
}

/// Shows only the parameter fields that the method in the menu (or, in compare mode, one of
/// the compared methods) reads: the others would change nothing.
pub(super) fn show_parameters() {
    let document = dom::document();
    let Some(algorithm) = document
        .get_element_by_id("algorithm")
        .and_then(|e| e.dyn_into::<web_sys::HtmlSelectElement>().ok())
        .and_then(|menu| Algorithm::from_name(&menu.value()))
    else {
        return;
    };
    let comparing = dom::checked("compare-on");
    for field in Field::ALL {
        if let Some(label) = document
            .get_element_by_id(field.id())
            .and_then(|e| e.parent_element())
            .and_then(|e| e.dyn_into::<web_sys::HtmlElement>().ok())
        {
            label.set_hidden(
                !(algorithms::uses(algorithm, field) || (comparing && compare::reads(field))),
            );
        }
    }
}

const SURFACE_COLOUR: [f32; 4] = [0.80, 0.72, 0.58, 1.0];

/// The layers of a selected mesh: its faces (flat, or coloured by each grid point's error when
/// the error toggle is on), its wireframe, and the original surface and kept points on request.
pub(super) fn mesh_layers(
    hf: &Heightfield,
    map: &ViewMapping,
    mesh: &ShownMesh,
    max_error: f64,
    toggles: ViewToggles,
) -> Vec<(Style, Geometry)> {
    let mut layers = Vec::new();
    if toggles.error {
        let err = &mesh.point_error;
        let scale = if max_error > 0.0 {
            1.0 / max_error
        } else {
            0.0
        };
        layers.push((
            Style::Fill,
            geometry::grid_surface(hf, map, &|i| geometry::error_colour(err[i] * scale)),
        ));
    } else {
        layers.push((
            Style::Fill,
            geometry::flat_mesh(hf, map, &mesh.triangles, SURFACE_COLOUR),
        ));
    }
    layers.push((
        Style::Lines,
        geometry::wireframe(hf, map, &mesh.triangles, [0.12, 0.12, 0.16, 1.0]),
    ));
    if toggles.original {
        layers.push((
            Style::Translucent,
            geometry::grid_surface(hf, map, &|_| [0.25, 0.45, 0.85, 0.35]),
        ));
    }
    if toggles.kept {
        layers.push((
            Style::Fill,
            geometry::markers(hf, map, &mesh.kept, map.step() * 1.2, [0.85, 0.1, 0.1, 1.0]),
        ));
    }
    layers
}

/// The offscreen test scene on the built-in surface: `"surface"` is the full-resolution surface
/// as first shown, `"mesh"` a simplified mesh (every 8th grid point of each 8th row) with its
/// wireframe and the error map, as the view shows a selection.
pub(super) fn test_scene(scene: &str) -> Result<Vec<(Style, Geometry)>, String> {
    let hf = Arc::new(crate::app::loader::builtin());
    let map = ViewMapping::new(&hf);
    match scene {
        "surface" => Ok(full_surface_layers(&hf, &map)),
        "mesh" => {
            let w = hf.width() as u32;
            let kept: Vec<u32> = (0..hf.len() as u32)
                .filter(|i| (i % w).is_multiple_of(8) && (i / w).is_multiple_of(8))
                .collect();
            let mesh = shown_mesh(&hf, &kept)?;
            let max_error = mesh.point_error.iter().cloned().fold(0.0, f64::max);
            let toggles = ViewToggles {
                original: false,
                error: true,
                kept: false,
            };
            Ok(mesh_layers(&hf, &map, &mesh, max_error, toggles))
        }
        other => Err(format!("unknown scene “{other}”: surface or mesh")),
    }
}

/// The layers shown when nothing is selected: the full-resolution surface, with its grid
/// wireframe when the grid is small enough to read.
fn full_surface_layers(hf: &Heightfield, map: &ViewMapping) -> Vec<(Style, Geometry)> {
    let mut layers = vec![(
        Style::Fill,
        geometry::grid_surface(hf, map, &|_| SURFACE_COLOUR),
    )];
    if hf.len() <= MAX_WIREFRAME_POINTS {
        layers.push((
            Style::Lines,
            geometry::wireframe(hf, map, &full_grid_triangles(hf), [0.35, 0.30, 0.25, 1.0]),
        ));
    }
    layers
}

/// The full grid's two triangles per cell, as grid indices.
fn full_grid_triangles(hf: &Heightfield) -> Vec<[u32; 3]> {
    let w = hf.width() as u32;
    let mut tris = Vec::with_capacity(hf.full_triangles());
    for y in 0..hf.height() as u32 - 1 {
        for x in 0..w - 1 {
            let a = y * w + x;
            tris.push([a, a + 1, a + w]);
            tris.push([a + 1, a + w + 1, a + w]);
        }
    }
    tris
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
