//! The page's top level: start-up, the per-frame update (optimise within the budget, the
//! panels, the plot, the 3-D view when it changed), loading files, exports, the panic hook and
//! the listeners of the main controls, the plot and the 3-D view. The views of share links,
//! teaching and compare mode are in their own modules; [`super::bindings`] is what the JS calls.

use super::costs::performance_now;
use super::costs::timed;
use super::dom::{self, by_id, listen};
use super::gpu::{BackendChoice, Renderer};
use super::page::{HIT_RADIUS, PlotKey, Ui, on_event, z_unit};
use super::{compare_view, plot_view, share_view, teaching_view};
use crate::app::algorithms;
use crate::app::camera::OrbitCamera;
use crate::app::geometry;
use crate::app::glb_export::mesh_glb;
use crate::app::loader;
use crate::app::plot::{self, EAxis, Layout, PlotPoint, Scene};
use crate::app::share::{FileFingerprint, ImportChoice, Origin};
use crate::app::state::{App, RunConfig, Surface, shown_mesh};
use crate::evaluator::Evaluator;
use crate::export::WorldMesh;
use crate::export::front_csv;
use crate::export::to_3mf;
use crate::export::to_obj;
use crate::export::to_ply;
use crate::export::to_stl;
use crate::export::{GlbMesh, vertex_normals, write_glb};
use crate::export::{SolidOptions, solid};
use crate::front::Solution;
use crate::front_file::FrontFile;
use crate::heightfield::Heightfield;
use crate::import::ImportOptions;
use crate::pick::Pick;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::prelude::*;
use web_sys::{HtmlCanvasElement, KeyboardEvent, MouseEvent, PointerEvent, WheelEvent};

/// Starts the app: panic hook, built-in surface, the 3-D view on the `#view` canvas (on the
/// backend `backends` says), listeners. The surface is drawn on the first [`frame`].
pub(super) async fn start(backends: BackendChoice) -> Result<Rc<RefCell<Ui>>, JsValue> {
    install_panic_hook();
    let hf = loader::builtin();
    let app = App::new(
        Surface {
            name: loader::BUILTIN_NAME.to_string(),
            heightfield: Arc::new(hf),
        },
        RunConfig::default(),
    );
    let mut ui = Ui::new(app, Origin::Builtin(loader::BUILTIN_NAME));
    dom::fill_algorithm_menu().map_err(|e| JsValue::from_str(&e))?;
    teaching_view::fill().map_err(|e| JsValue::from_str(&e))?;
    share_view::fill_menus(&ui.app).map_err(|e| JsValue::from_str(&e))?;
    share_view::update_share_controls(&ui);
    dom::write_config(ui.app.config()).map_err(|e| JsValue::from_str(&e))?;
    super::page::show_parameters();
    ui.surface_info();
    by_id::<web_sys::HtmlElement>("legend-bar")
        .map_err(|e| JsValue::from_str(&e))?
        .style()
        .set_property("background", &geometry::error_legend_css())?;
    let canvas = by_id::<HtmlCanvasElement>("view").map_err(|e| JsValue::from_str(&e))?;
    let dpr = web_sys::window().map_or(1.0, |w| w.device_pixel_ratio());
    canvas.set_width(((canvas.client_width() as f64) * dpr).round().max(1.0) as u32);
    canvas.set_height(((canvas.client_height() as f64) * dpr).round().max(1.0) as u32);
    match Renderer::new(canvas, backends).await {
        Ok(r) => {
            dom::set_text("backend", r.backend);
            ui.renderer = Some(r);
        }
        Err(e) => dom::set_text("backend", &format!("no 3-D view: {e}")),
    }
    // The WebGL2 fallback may have put a fresh copy of the canvas in its place.
    let canvas = by_id::<HtmlCanvasElement>("view").map_err(|e| JsValue::from_str(&e))?;
    ui.selection_info();
    let ui = Rc::new(RefCell::new(ui));
    wire(&ui, &canvas).map_err(|e| JsValue::from_str(&e))?;
    share_view::wire(&ui).map_err(|e| JsValue::from_str(&e))?;
    teaching_view::wire(&ui).map_err(|e| JsValue::from_str(&e))?;
    Ok(ui)
}

/// Shows a panic on the page (and the console) instead of a silently frozen app.
fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let message = info.to_string();
        web_sys::console::error_1(&format!("ParetoMesh panicked: {message}").into());
        dom::set_text("panic-message", &message);
        dom::set_visible("panic", true);
    }));
}

/// One animation frame: optimise within the budget, update the status, the panels, the plot
/// and the 3-D view.
pub(super) fn frame(ui: &mut Ui) {
    timed("frame", || frame_steps(ui));
}

fn frame_steps(ui: &mut Ui) {
    let budget = ui.app.config().budget_ms;
    let mut clock = performance_now;
    timed("tick", || ui.app.tick(budget, &mut clock));
    compare_view::compare_frame(ui);
    let mut status = dom::status_text(&ui.app.status(), ui.app.is_running());
    if let Some(r) = ui.app.reproduction() {
        status.push_str(&format!(
            " · re-running the shared run to generation {}",
            r.generations
        ));
    }
    super::pool::note_status(ui, &mut status);
    dom::set_text("status", &status);
    teaching_view::teaching_frame(ui, performance_now());
    timed("layers", || ui.update_layers());
    timed("plot", || draw_plot(ui));
    ui.resize_view();
    if ui.redraw
        && let Some(r) = ui.renderer.as_mut()
    {
        timed("draw", || r.draw(&ui.camera));
        ui.redraw = false;
        if !ui.painted {
            // Lets anyone (the end-to-end test, DevTools) read the time to first paint.
            ui.painted = true;
            if let Some(p) = web_sys::window().and_then(|w| w.performance()) {
                let _ = p.mark("paretomesh-first-paint");
            }
        }
    }
}

/// Draws the plot: the teaching plot when that view shows a phase, else the population and the
/// front, and keeps the layout for hit-testing.
fn draw_plot(ui: &mut Ui) {
    let Some((ctx, cw, ch)) = dom::canvas_2d("plot") else {
        return;
    };
    let unit = z_unit(&ui.app.surface().heightfield);
    if let Some(layout) = teaching_view::draw_teaching_plot(ui, &ctx, cw, ch, &unit) {
        ui.plot_layout = layout;
        ui.front_points.clear();
        ui.plot_key = None;
        return;
    }
    let e_axis = e_axis();
    // Redrawing a front of thousands of members costs milliseconds: only when it changed.
    let key = PlotKey {
        revision: ui.app.revision(),
        hovered: ui.hovered,
        selected: ui.app.selected_front_index(),
        size: (cw, ch),
        e_axis,
        log_e: dom::checked("plot-log-e"),
    };
    if ui.plot_key.as_ref() == Some(&key) {
        return;
    }
    ui.plot_key = Some(key);
    let grid_points = ui.app.surface().heightfield.len();
    let members: &[Solution] = ui.app.front().map_or(&[], |f| f.solutions());
    ui.front_points = members
        .iter()
        .map(|s| PlotPoint {
            t: s.t as f64,
            e: e_axis.value(s, grid_points),
        })
        .collect();
    let labels: Vec<String> = members
        .iter()
        .map(|s| plot::hover_text(s, grid_points, &unit))
        .collect();
    // The population carries E_sum only: it is drawn on the sum and mean axes.
    let population: Vec<(PlotPoint, usize)> = match (e_axis, ui.app.optimizer()) {
        (EAxis::Max, _) | (_, None) => Vec::new(),
        (_, Some(o)) => o
            .population_points()
            .into_iter()
            .map(|(t, e, rank)| {
                let e = if e_axis == EAxis::Mean {
                    e / grid_points.max(1) as f64
                } else {
                    e
                };
                (PlotPoint { t, e }, rank)
            })
            .collect(),
    };
    ui.plot_layout = Layout::fit_scaled(
        cw,
        ch,
        ui.front_points
            .iter()
            .chain(population.iter().map(|(p, _)| p)),
        dom::checked("plot-log-e"),
    );
    plot_view::draw(
        &ctx,
        &ui.plot_layout,
        &Scene {
            population: &population,
            front: &ui.front_points,
            selected: ui.app.selected_front_index(),
            hovered: ui.hovered,
            z_unit: &unit,
            e_axis,
            labels: &labels,
        },
    );
}

/// The error the plot's E axis shows, from the page's menu (E_sum when it is missing).
fn e_axis() -> EAxis {
    dom::by_id::<web_sys::HtmlSelectElement>("plot-e-axis")
        .ok()
        .and_then(|menu| EAxis::from_key(&menu.value()))
        .unwrap_or_default()
}

/// Shows a parsed file whose bytes have `fingerprint`; when a share link waits for a file,
/// only that file is accepted and the link's run follows.
pub(super) fn load(
    ui: &mut Ui,
    fingerprint: FileFingerprint,
    parsed: Result<Heightfield, String>,
) -> bool {
    let name = fingerprint.name.clone();
    match parsed {
        Ok(hf) => {
            let link = match share_view::check_awaited_file(ui, &fingerprint) {
                Ok(link) => link,
                Err(e) => {
                    dom::show_load_message(&e, true);
                    return false;
                }
            };
            share_view::set_surface(ui, &name, hf, Origin::File(fingerprint));
            dom::show_load_message(&format!("loaded {name}"), false);
            if let Some(link) = link {
                share_view::apply_run(ui, &link);
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

/// Downloads the front (`json`, `csv`) or the shown mesh (`ply`, `obj`, `stl`, `glb`).
fn export(ui: &Ui, kind: &str) -> Result<(), String> {
    let name = &ui.app.surface().name;
    let stem = name.rsplit_once('.').map_or(name.as_str(), |(a, _)| a);
    match kind {
        "json" => export_front_file(ui, stem),
        "tiles" => dom::download(
            &format!("{stem}_3dtiles.zip"),
            "application/zip",
            &ui.app.pyramid_zip()?,
        ),
        "csv" => {
            let front = ui.app.front().ok_or(EMPTY_FRONT)?;
            dom::download(
                &format!("{stem}_front.csv"),
                "text/csv",
                front_csv(front.solutions()).as_bytes(),
            )
        }
        _ => export_mesh(ui, stem, kind),
    }
}

const EMPTY_FRONT: &str = "run an algorithm first: the front is empty";

/// Downloads the front as front.json, the file `paretomesh run` writes.
fn export_front_file(ui: &Ui, stem: &str) -> Result<(), String> {
    if let Some(tiled) = ui.app.tiled_run() {
        let status = ui.app.status();
        let workers = ui.app.pool_setup().workers;
        let file = tiled.run_file(
            &ui.app.surface().heightfield,
            status.elapsed_ms.round() as u64,
            workers,
        )?;
        let json = serde_json::to_string(&file).map_err(|e| e.to_string())?;
        return dom::download(
            &format!("{stem}_front.json"),
            "application/json",
            json.as_bytes(),
        );
    }
    let front = ui.app.front().ok_or(EMPTY_FRONT)?;
    let config = ui.app.config();
    let status = ui.app.status();
    let file = FrontFile::new(
        &mut Evaluator::new(ui.app.surface().heightfield.clone()),
        &algorithms::config(config.algorithm, &config.params),
        config.params.seed,
        status.evaluations,
        status.elapsed_ms.round() as u64,
        front,
    )
    .map_err(|e| e.to_string())?;
    // A mesh resampled through the import dialog records that choice, so that `paretomesh
    // export` reads the file into the same grid.
    let file = match &ui.origin {
        Origin::File(FileFingerprint {
            import: Some(choice),
            ..
        }) => file.with_import(&choice.options()?),
        _ => file.with_import(&ImportOptions::default()),
    };
    let json = serde_json::to_string_pretty(&file).map_err(|e| e.to_string())?;
    dom::download(
        &format!("{stem}_front.json"),
        "application/json",
        json.as_bytes(),
    )
}

/// Downloads the shown mesh (the full grid when nothing is selected) in the input's own
/// coordinates as `kind`: PLY, OBJ, STL or binary glTF (with the error map as vertex colours
/// when it is shown); closed into a printable solid when "solid" is ticked. A 3MF, which is
/// for printing, is always the solid.
fn export_mesh(ui: &Ui, stem: &str, kind: &str) -> Result<(), String> {
    let s = ui.app.surface();
    let hf = &s.heightfield;
    // The selected mesh itself, also when the view draws a coarser member in its place.
    let mesh = match &ui.shown {
        Some(m) if ui.app.selected().is_some_and(|s| s.t == m.triangles.len()) => m.clone(),
        _ => match ui.app.selected_mesh(None) {
            Some(m) => m?,
            None => shown_mesh(hf, &ui.app.shown_kept())?,
        },
    };
    let as_solid = kind == "3mf" || dom::checked("export-solid");
    let world = if as_solid {
        solid(hf, &mesh.triangles, &SolidOptions::default()).map_err(|e| e.to_string())?
    } else {
        WorldMesh::new(hf, &mesh.kept, &mesh.triangles)?
    };
    let note = format!(
        "ParetoMesh simplification of {}: {} vertices, {} triangles, E = {}",
        s.name,
        mesh.kept.len(),
        mesh.triangles.len(),
        mesh.e_sum
    );
    let name = format!(
        "{stem}_{}t{}.{kind}",
        mesh.triangles.len(),
        if as_solid { "_solid" } else { "" }
    );
    match kind {
        "glb" if as_solid => {
            let indices: Vec<u32> = world.triangles.iter().flatten().copied().collect();
            let normals = vertex_normals(&world.vertices, &indices);
            let bytes = write_glb(&GlbMesh {
                positions: &world.vertices,
                normals: &normals,
                indices: &indices,
                colors: None,
            })
            .map_err(|e| e.to_string())?;
            dom::download(&name, "model/gltf-binary", &bytes)
        }
        "ply" => dom::download(
            &name,
            "application/octet-stream",
            to_ply(&world, &note).as_bytes(),
        ),
        "obj" => dom::download(&name, "text/plain", to_obj(&world, &note).as_bytes()),
        "stl" => dom::download(&name, "application/octet-stream", &to_stl(&world, &note)),
        "3mf" => dom::download(
            &name,
            "model/3mf",
            &to_3mf(&world, &format!("{} solid", s.name))?,
        ),
        "glb" => dom::download(
            &name,
            "model/gltf-binary",
            &mesh_glb(hf, &mesh, ui.toggles().error)?,
        ),
        _ => Err(format!("unknown export kind {kind}")),
    }
}

/// How a parsed file became a grid, for its share links: `None` for a file that is a grid, else
/// the projection chosen (`"auto"` when none was), the grid size it gave and the surface kept
/// (`None` for a single one).
pub(super) fn import_choice(
    parsed: &Result<Heightfield, String>,
    projection: Option<String>,
    surface: Option<String>,
) -> Option<ImportChoice> {
    let hf = parsed.as_ref().ok().filter(|hf| hf.resampled())?;
    Some(ImportChoice {
        projection: projection.unwrap_or_else(|| "auto".to_string()),
        width: hf.width() as u32,
        height: hf.height() as u32,
        surface: surface.filter(|s| s != "single"),
    })
}

/// The listeners of the main controls, the plot and the 3-D view, then compare mode's.
fn wire(ui: &Rc<RefCell<Ui>>, canvas: &HtmlCanvasElement) -> Result<(), String> {
    wire_controls(ui)?;
    wire_plot(ui)?;
    wire_view(ui, canvas);
    compare_view::wire(ui)
}

/// Run, pause, step, reset, the parameter form, the view toggles and the export buttons.
fn wire_controls(ui: &Rc<RefCell<Ui>>) -> Result<(), String> {
    let on = |id: &str, event: &str, f: Box<dyn Fn(&mut Ui)>| on_event(ui, id, event, f);
    on(
        "run",
        "click",
        Box::new(|ui| start_run(ui, |app| app.run())),
    )?;
    on("pause", "click", Box::new(|ui| ui.app.pause()))?;
    on(
        "step",
        "click",
        Box::new(|ui| start_run(ui, |app| app.step_once().map(drop))),
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
    for (id, rule) in [
        ("select-knee", Pick::Knee),
        ("select-tradeoff", Pick::TradeOff),
    ] {
        on(
            id,
            "click",
            Box::new(move |ui| {
                if ui.app.select_by(rule) {
                    ui.update_layers();
                }
            }),
        )?;
    }
    on(
        "reset-view",
        "click",
        Box::new(|ui| {
            ui.camera = OrbitCamera::default();
            ui.redraw = true;
        }),
    )?;
    for kind in ["ply", "obj", "stl", "glb", "3mf", "tiles", "csv", "json"] {
        on(
            &format!("export-{kind}"),
            "click",
            Box::new(move |ui| {
                let message = export(ui, kind).err().unwrap_or_default();
                dom::set_text("export-message", &message);
            }),
        )?;
    }
    Ok(())
}

/// Applies the form, then runs or steps the app (`go`); a refusal shows under the form.
fn start_run(ui: &mut Ui, go: fn(&mut App) -> Result<(), String>) {
    if ui.apply_form()
        && let Err(e) = go(&mut ui.app)
    {
        dom::set_text("run-message", &e);
    }
}

/// The plot: hover, click, arrow keys.
fn wire_plot(ui: &Rc<RefCell<Ui>>) -> Result<(), String> {
    let plot: HtmlCanvasElement = by_id("plot")?;
    let u = ui.clone();
    listen(&plot, "mousemove", move |e: MouseEvent| {
        plot_hover(
            &mut u.borrow_mut(),
            e.offset_x() as f64,
            e.offset_y() as f64,
        );
    });
    let u = ui.clone();
    listen(&plot, "mouseleave", move |_: MouseEvent| {
        u.borrow_mut().hovered = None
    });
    let u = ui.clone();
    listen(&plot, "click", move |e: MouseEvent| {
        plot_click(
            &mut u.borrow_mut(),
            e.offset_x() as f64,
            e.offset_y() as f64,
        );
    });
    let u = ui.clone();
    listen(&plot, "keydown", move |e: KeyboardEvent| {
        let delta = match e.key().as_str() {
            "ArrowRight" | "ArrowUp" => 1,
            "ArrowLeft" | "ArrowDown" => -1,
            _ => return,
        };
        e.prevent_default();
        let mut ui = u.borrow_mut();
        ui.app.move_selection(delta);
        ui.update_layers();
    });
    Ok(())
}

/// The mouse at (`x`, `y`) over the plot: the teaching plot's read-out when it is shown, else
/// the hovered front member.
fn plot_hover(ui: &mut Ui, x: f64, y: f64) {
    let layout = ui.plot_layout;
    if teaching_view::teaching_hover(ui, &layout, x, y) {
        return;
    }
    ui.hovered = plot::hit_test(&ui.plot_layout, &ui.front_points, x, y, HIT_RADIUS);
}

/// A click at (`x`, `y`) on the plot selects the front member there, if any.
fn plot_click(ui: &mut Ui, x: f64, y: f64) {
    if let Some(i) = plot::hit_test(&ui.plot_layout, &ui.front_points, x, y, HIT_RADIUS) {
        ui.app.select_front_index(Some(i));
        ui.update_layers();
    }
}

/// The 3-D view: one pointer orbits (pans with the right button or Shift), two pinch.
fn wire_view(ui: &Rc<RefCell<Ui>>, canvas: &HtmlCanvasElement) {
    let u = ui.clone();
    let c = canvas.clone();
    listen(canvas, "pointerdown", move |e: PointerEvent| {
        let _ = c.set_pointer_capture(e.pointer_id());
        let mut ui = u.borrow_mut();
        ui.pointers.retain(|p| p.0 != e.pointer_id());
        ui.pointers
            .push((e.pointer_id(), e.client_x() as f64, e.client_y() as f64));
    });
    let u = ui.clone();
    let c = canvas.clone();
    listen(canvas, "pointermove", move |e: PointerEvent| {
        pointer_move(&mut u.borrow_mut(), &e, c.client_height() as f32);
    });
    for event in ["pointerup", "pointercancel"] {
        let u = ui.clone();
        listen(canvas, event, move |e: PointerEvent| {
            u.borrow_mut().pointers.retain(|p| p.0 != e.pointer_id());
        });
    }
    let u = ui.clone();
    listen(canvas, "wheel", move |e: WheelEvent| {
        e.prevent_default();
        let mut ui = u.borrow_mut();
        ui.camera.zoom((e.delta_y() * 0.0015).exp() as f32);
        ui.redraw = true;
    });
    listen(canvas, "contextmenu", |e: MouseEvent| e.prevent_default());
}

/// A tracked pointer moved over the 3-D view (`height` CSS pixels tall): with two pointers
/// down, pinch zoom and pan; with one, pan (right or middle button, or Shift) or orbit.
fn pointer_move(ui: &mut Ui, e: &PointerEvent, height: f32) {
    let Some(k) = ui.pointers.iter().position(|p| p.0 == e.pointer_id()) else {
        return;
    };
    let (x, y) = (e.client_x() as f64, e.client_y() as f64);
    let (_, px, py) = ui.pointers[k];
    let (dx, dy) = ((x - px) as f32, (y - py) as f32);
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
}
