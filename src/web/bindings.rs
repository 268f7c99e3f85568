//! Everything the page's JavaScript calls (`index.html`, `www/main.js`, `www/worker.js`): the
//! [`WebApp`] handle with its start-up and frame, file loading and read-only accessors for the
//! end-to-end tests, and the free functions the Worker and the import dialog use.

use super::costs::timed;
use super::gpu::BackendChoice;
use super::page::Ui;
use super::{dom, pool, preview, share_view, teaching_view, transfer, ui};
use crate::app::compare::METHODS;
use crate::app::loader;
use crate::app::pool::PoolSetup;
use crate::app::share::{FileFingerprint, fnv1a64};
use crate::evaluator::Evaluator;
use crate::import::{ImportOptions, raw};
use crate::optimizer::Progress;
use js_sys::Reflect;
use std::cell::RefCell;
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// The app as the page's JS sees it.
#[wasm_bindgen]
pub struct WebApp {
    pub(super) ui: Rc<RefCell<Ui>>,
}

/// Starts the app: panic hook, built-in surface, the 3-D view on the `#view` canvas (WebGL2 only when
/// `force_webgl`; with `fail_webgpu`, WebGPU with a device request the browser refuses, which
/// shows the fallback to WebGL2), listeners. The surface is drawn on the first
/// [`WebApp::frame`].
#[wasm_bindgen]
pub async fn start(force_webgl: bool, fail_webgpu: bool) -> Result<WebApp, JsValue> {
    let backends = if force_webgl {
        BackendChoice::WebGl2
    } else if fail_webgpu {
        BackendChoice::FailingWebGpu
    } else {
        BackendChoice::Auto
    };
    Ok(WebApp {
        ui: ui::start(backends).await?,
    })
}

#[wasm_bindgen]
impl WebApp {
    /// One animation frame: optimise within the budget, update the status, plot and view.
    pub fn frame(&self, _now: f64) {
        ui::frame(&mut self.ui.borrow_mut());
    }

    /// Loads a dropped or picked file (`sidecar` for a .f32 grid). On failure the message shows
    /// next to the drop zone and the current surface stays. Returns whether it loaded.
    #[wasm_bindgen(js_name = loadFile)]
    pub fn load_file(&self, name: &str, bytes: &[u8], sidecar: Option<Vec<u8>>) -> bool {
        let parsed = loader::parse(name, bytes, sidecar.as_deref(), &ImportOptions::default());
        let fingerprint = FileFingerprint {
            import: ui::import_choice(&parsed, None, None),
            ..FileFingerprint::of(name, bytes)
        };
        ui::load(&mut self.ui.borrow_mut(), fingerprint, parsed)
    }

    /// Shows a surface the Worker parsed (see [`super::transfer`]) from a file of `size` bytes
    /// whose FNV-1a hash is `hash` (16 hex digits, from [`fnv1a64_hex`], which the Worker runs
    /// on the file's bytes); like [`WebApp::load_file`] otherwise. `projection` is the import
    /// dialog's projection for a mesh that had to be resampled ("auto" when absent) and
    /// `surface` its surface choice ("single" when absent): with the grid's size they go into
    /// share links of this surface.
    #[wasm_bindgen(js_name = loadParsed)]
    pub fn load_parsed(
        &self,
        name: &str,
        parsed: JsValue,
        size: f64,
        hash: &str,
        projection: Option<String>,
        surface: Option<String>,
    ) -> bool {
        let parsed = transfer::surface_from_js(&parsed).map_err(|e| format!("{name}: {e}"));
        let fingerprint = FileFingerprint {
            name: name.to_string(),
            size: size as u64,
            fnv1a64: u64::from_str_radix(hash, 16).unwrap_or(0),
            import: ui::import_choice(&parsed, projection, surface),
        };
        ui::load(&mut self.ui.borrow_mut(), fingerprint, parsed)
    }

    /// The import choice (`{projection, width, height, surface?}`) of the file a share link waits for,
    /// or null: the page then re-parses a dropped mesh that way instead of asking.
    #[wasm_bindgen(js_name = pendingImport)]
    pub fn pending_import(&self) -> JsValue {
        share_view::awaited_import(&self.ui.borrow())
            .and_then(|choice| serde_wasm_bindgen::to_value(&choice).ok())
            .unwrap_or(JsValue::NULL)
    }

    /// Opens a share link (the URL hash, with or without `#`); see [`super::share_view`].
    #[wasm_bindgen(js_name = openLink)]
    pub fn open_link(&self, hash: &str) {
        share_view::open_link(&mut self.ui.borrow_mut(), hash);
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

    /// Selects the front member at `index` (by increasing T) as a click on its point in the
    /// plot does; none when out of range.
    #[wasm_bindgen(js_name = selectFrontMember)]
    pub fn select_front_member(&self, index: usize) {
        let mut ui = self.ui.borrow_mut();
        ui.app.select_front_index(Some(index));
        ui.update_layers();
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
        let phase = teaching_view::teaching_phase(&ui)?;
        let generation = ui
            .app
            .optimizer()
            .and_then(|o| o.generation_trace())
            .map_or(0, |t| t.generation);
        Some(vec![phase.label().to_string(), generation.to_string()])
    }
}

/// Pool runs (see [`crate::app::pool`]): what `www/pool.js` calls to hand jobs to its workers
/// and pass on what they post.
#[wasm_bindgen]
impl WebApp {
    /// Runs go to `workers` Web Workers (at least one): grids with a side over `tile` points
    /// (0: the CLI's default tile size), cut into tiles, always; others too when `always` (else
    /// they run in the frame loop).
    #[wasm_bindgen(js_name = setPoolSetup)]
    pub fn set_pool_setup(&self, workers: usize, always: bool, tile: usize) -> Result<(), JsError> {
        let tile = if tile == 0 {
            crate::tiling::DEFAULT_TILE
        } else {
            tile
        };
        if tile < crate::tiling::MIN_TILE {
            return Err(JsError::new(&format!(
                "tiles need at least {} points a side, not {tile}",
                crate::tiling::MIN_TILE
            )));
        }
        self.ui.borrow_mut().app.set_pool_setup(PoolSetup {
            workers: workers.max(1),
            always,
            tile,
        });
        Ok(())
    }

    /// Workers a pool run uses.
    #[wasm_bindgen(js_name = poolWorkers)]
    pub fn pool_workers(&self) -> usize {
        self.ui.borrow().app.pool_setup().workers
    }

    /// The id of the pool run under way, or 0 when none is (no pool run, or it ended or
    /// failed): the page then stops the workers still busy with an older run.
    #[wasm_bindgen(js_name = poolRunId)]
    pub fn pool_run_id(&self) -> f64 {
        let mut ui = self.ui.borrow_mut();
        ui.app
            .pool_run()
            .filter(|p| !crate::optimizer::Optimizer::progress(&**p).done)
            .map_or(0.0, |p| p.id() as f64)
    }

    /// The next job of the pool run for a free worker (see [`pool::job_to_js`]), or null.
    #[wasm_bindgen(js_name = takePoolJob)]
    pub fn take_pool_job(&self) -> Result<JsValue, JsValue> {
        let mut ui = self.ui.borrow_mut();
        let hf = ui.app.surface().heightfield.clone();
        let Some(run) = ui.app.pool_run() else {
            return Ok(JsValue::NULL);
        };
        let Some(job) = run.next_job() else {
            return Ok(JsValue::NULL);
        };
        timed("job hand-out", || {
            pool::job_to_js(&job, &hf, run.tiled().map(|t| t.plan()))
        })
    }

    /// A worker posts tile job `index` of pool run `run` done, with the tile's front as JSON.
    /// A front that does not fit ends the run with its message.
    #[wasm_bindgen(js_name = poolReportTile)]
    pub fn pool_report_tile(&self, run: f64, index: usize, front: &str) {
        let mut ui = self.ui.borrow_mut();
        let applied = timed("tile front parse", || serde_json::from_str(front))
            .map_err(|e| format!("a worker posted a tile front the page cannot read: {e}"))
            .and_then(|front| {
                timed("tile front report", || {
                    ui.app.pool_report_tile(run as u64, index, front)
                })
            });
        if let Err(e) = applied {
            ui.app.pool_failed(run as u64, Some(index), &e);
        }
    }

    /// A worker posts job `index` of pool run `run`: its front (as [`pool::front_to_js`]'s
    /// arrays) and progress. A report that does not fit ends the run with its message.
    #[wasm_bindgen(js_name = poolReport)]
    #[allow(clippy::too_many_arguments)]
    pub fn pool_report(
        &self,
        run: f64,
        index: usize,
        scores: Vec<f64>,
        offsets: Vec<u32>,
        kept: Vec<u32>,
        evaluations: f64,
        generation: f64,
        done: bool,
    ) {
        let mut ui = self.ui.borrow_mut();
        let progress = Progress {
            evaluations: evaluations as u64,
            generation: generation as u64,
            done,
        };
        let applied = pool::front_from_arrays(scores, offsets, kept)
            .and_then(|front| ui.app.pool_report(run as u64, index, front, progress));
        if let Err(e) = applied {
            ui.app.pool_failed(run as u64, Some(index), &e);
        }
    }

    /// A worker failed on job `index` of pool run `run` (−1: the page could not hand out a
    /// job): the run stops and `message` shows.
    #[wasm_bindgen(js_name = poolFailed)]
    pub fn pool_failed(&self, run: f64, index: f64, message: &str) {
        let index = (index >= 0.0).then_some(index as usize);
        self.ui
            .borrow_mut()
            .app
            .pool_failed(run as u64, index, message);
    }
}

/// Runs a tile job in a worker of the pool and returns the tile's front as JSON; see
/// [`pool::run_tile`].
#[wasm_bindgen(js_name = runTile)]
pub fn run_tile(
    surface: JsValue,
    plan: &str,
    tile: usize,
    config: &str,
    seed: &str,
    members: usize,
) -> Result<String, JsError> {
    pool::run_tile(&surface, plan, tile, config, seed, members).map_err(|e| JsError::new(&e))
}

/// A job running in a Web Worker of the pool (`www/pool-worker.js`); see [`pool::JobRunner`].
#[wasm_bindgen(js_name = JobRunner)]
pub struct JobRunnerHandle {
    runner: pool::JobRunner,
}

#[wasm_bindgen(js_class = JobRunner)]
impl JobRunnerHandle {
    /// Builds the job's algorithm (menu key) with `params` (JSON) on `surface` (the job's grid
    /// in [`transfer`]'s form).
    #[wasm_bindgen(constructor)]
    pub fn new(
        surface: JsValue,
        algorithm: &str,
        params: &str,
    ) -> Result<JobRunnerHandle, JsError> {
        let runner =
            pool::JobRunner::new(&surface, algorithm, params).map_err(|e| JsError::new(&e))?;
        Ok(Self { runner })
    }

    /// Steps for about `ms` milliseconds or until done; returns `[evaluations, generation,
    /// done (0 or 1)]`.
    #[wasm_bindgen(js_name = runFor)]
    pub fn run_for(&mut self, ms: f64) -> Vec<f64> {
        let p = self.runner.run_for(ms);
        vec![
            p.evaluations as f64,
            p.generation as f64,
            f64::from(u8::from(p.done)),
        ]
    }

    /// The job's front so far as `{scores, offsets, kept}` typed arrays.
    pub fn front(&self) -> Result<JsValue, JsError> {
        pool::front_to_js(self.runner.front())
            .map_err(|_| JsError::new("cannot pass the front to the page"))
    }
}

thread_local! {
    static LAST_PANIC: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Keeps a panic's message in the worker that runs this, for [`last_panic`]: a panicking job
/// throws a bare `RuntimeError`, and its worker reports the message instead.
#[wasm_bindgen(js_name = keepPanicMessages)]
pub fn keep_panic_messages() {
    std::panic::set_hook(Box::new(|info| {
        let message = info.to_string();
        LAST_PANIC.with(|p| *p.borrow_mut() = Some(message));
    }));
}

/// The message of the last panic since [`keep_panic_messages`], if any.
#[wasm_bindgen(js_name = lastPanic)]
pub fn last_panic() -> Option<String> {
    LAST_PANIC.with(|p| p.borrow().clone())
}

/// FNV-1a hash of `bytes` as 16 hex digits: the fingerprint a share link gives a user's file.
#[wasm_bindgen(js_name = fnv1a64Hex)]
pub fn fnv1a64_hex(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a64(bytes))
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

    /// The plot's read-out of the front member under the mouse (T, E_sum, mean and E_max in the
    /// surface's units), if any.
    #[wasm_bindgen(js_name = hoveredText)]
    pub fn hovered_text(&self) -> Option<String> {
        let ui = self.ui.borrow();
        let member = ui.app.front()?.solutions().get(ui.hovered?)?;
        let hf = &ui.app.surface().heightfield;
        Some(crate::app::plot::hover_text(
            member,
            hf.len(),
            &super::page::z_unit(hf),
        ))
    }

    /// Vertices of the selected mesh (kept points, corners included), if one is selected.
    #[wasm_bindgen(js_name = selectedVertexCount)]
    pub fn selected_vertex_count(&self) -> Option<usize> {
        self.ui.borrow().shown.as_ref().map(|m| m.kept.len())
    }

    /// Triangles of the mesh the 3-D view draws for the selection, if one is selected.
    #[wasm_bindgen(js_name = shownTriangleCount)]
    pub fn shown_triangle_count(&self) -> Option<usize> {
        self.ui.borrow().shown.as_ref().map(|m| m.triangles.len())
    }

    /// Name of the loaded surface.
    #[wasm_bindgen(js_name = surfaceName)]
    pub fn surface_name(&self) -> String {
        self.ui.borrow().app.surface().name.clone()
    }
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

    /// True once every method of the comparison have finished.
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

/// Loads a raw f32 grid with its JSON sidecar, scores the kept indices, and returns the
/// evaluation as a JS object `{E_sum, E_max, rms, T, triangles}`.
#[wasm_bindgen(js_name = evaluateRaw)]
pub fn evaluate_raw(grid: &[u8], sidecar: &[u8], kept: &[u32]) -> Result<JsValue, JsError> {
    let hf = raw::parse(grid, sidecar, "upload").map_err(|e| JsError::new(&e.to_string()))?;
    let evaluation = Evaluator::new(std::sync::Arc::new(hf))
        .evaluate(kept)
        .map_err(|e| JsError::new(&e.to_string()))?;
    // JSON-compatible: plain objects (not `Map`s) for the flattened score.
    let serializer = serde_wasm_bindgen::Serializer::json_compatible();
    serde::Serialize::serialize(&evaluation, &serializer).map_err(|e| JsError::new(&e.to_string()))
}

/// Parses a file (in the Worker) with the dialog's options (see [`loader::options`] and
/// [`loader::surface`]) and returns the plain-object height field with `resampled: true` when a
/// mesh was projected and resampled or a GeoTIFF was over the size limit (the page then offers
/// the import dialog), and `georeferenceSummary`: the GeoTIFF's georeferencing and nodata
/// summary (null for other files). On failure it throws an `Error` with the message for the user and
/// `folds: true` when the file is a mesh whose outer surface can still be imported.
#[wasm_bindgen(js_name = parseSurface)]
pub fn parse_surface(
    name: &str,
    bytes: &[u8],
    sidecar: Option<Vec<u8>>,
    projection: &str,
    surface: &str,
    grid_width: u32,
    grid_height: u32,
) -> Result<JsValue, JsValue> {
    let error = |message: &str, folds: bool| -> JsValue {
        let e = js_sys::Error::new(message);
        let _ = Reflect::set(&e, &"folds".into(), &folds.into());
        e.into()
    };
    let mut options =
        loader::options(projection, grid_width, grid_height).map_err(|e| error(&e, false))?;
    options.surface = loader::surface(surface).map_err(|e| error(&e, false))?;
    let hf = loader::parse_file(name, bytes, sidecar.as_deref(), &options)
        .map_err(|e| error(&e.message, e.folds))?;
    let handoff = || error("cannot pass the parsed surface to the page", false);
    let o = transfer::surface_to_js(&hf).map_err(|_| handoff())?;
    let summary = loader::georeference_summary(&hf).map_or(JsValue::NULL, JsValue::from);
    Reflect::set(&o, &"georeferenceSummary".into(), &summary).map_err(|_| handoff())?;
    Ok(o)
}

/// Draws a parsed surface (the Worker's plain-object form) on canvas `canvas_id`, one pixel per
/// grid point, scaled to the canvas by CSS.
#[wasm_bindgen(js_name = drawPreview)]
pub fn draw_preview(canvas_id: &str, surface: JsValue) -> Result<(), JsError> {
    let hf = transfer::surface_from_js(&surface).map_err(|e| JsError::new(&e))?;
    preview::draw(canvas_id, &hf).map_err(|e| JsError::new(&e))
}

/// Renders test scene `scene` ("surface" or "mesh", see [`super::page::test_scene`]) with
/// `backend` ("webgpu" or "webgl2") into an offscreen `width` × `height` texture and resolves
/// to `{backend, width, height, pixels}`: the RGBA8 pixels read back from the GPU, top row
/// first. The end-to-end test compares the two backends with it.
#[wasm_bindgen(js_name = renderOffscreen)]
pub async fn render_offscreen(
    backend: String,
    scene: String,
    width: u32,
    height: u32,
) -> Result<JsValue, JsError> {
    if !(1..=4096).contains(&width) || !(1..=4096).contains(&height) {
        return Err(JsError::new("the size must be 1 to 4096 pixels per side"));
    }
    let layers = super::page::test_scene(&scene).map_err(|e| JsError::new(&e))?;
    let camera = crate::app::camera::OrbitCamera::default();
    let (name, pixels) = super::gpu::render_offscreen(&backend, (width, height), &camera, layers)
        .await
        .map_err(|e| JsError::new(&e))?;
    let o = js_sys::Object::new();
    let set = |k: &str, v: JsValue| Reflect::set(&o, &k.into(), &v);
    set("backend", name.into())
        .and(set("width", width.into()))
        .and(set("height", height.into()))
        .and(set("pixels", js_sys::Uint8Array::from(&pixels[..]).into()))
        .map_err(|_| JsError::new("cannot pass the pixels to the page"))?;
    Ok(o.into())
}
