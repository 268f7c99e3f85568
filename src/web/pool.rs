//! Both sides of a pool run (see [`crate::app::pool`]) at the JavaScript boundary: the job a
//! worker is handed (`www/pool.js` asks for it, `www/pool-worker.js` runs it), the worker's
//! runner, and the front it posts back as three transferable typed arrays.

use super::transfer;
use crate::app::algorithms::{self, Algorithm, Params, Running};
use crate::app::pool::{FrontParts, Job, Work};
use crate::catalogue::Config;
use crate::front::Front;
use crate::heightfield::Heightfield;
use crate::optimizer::Progress;
use crate::tiling::{self, TilePlan};
use js_sys::{Float64Array, Object, Reflect, Uint32Array};
use wasm_bindgen::prelude::*;

/// `value` as JSON text.
fn json<T: serde::Serialize>(value: &T) -> Result<String, JsValue> {
    serde_json::to_string(value).map_err(|e| JsValue::from_str(&e.to_string()))
}

fn set(o: &Object, key: &str, value: &JsValue) -> Result<(), JsValue> {
    Reflect::set(o, &key.into(), value).map(|_| ())
}

/// The message a worker is handed for `job` on the surface `hf`: `{run, index, kind, surface}`
/// with `surface` (the job's own grid: the whole grid, or its tile cut from it) in
/// [`transfer`]'s form, whose heights the page transfers. A whole-grid job (`kind: "whole"`)
/// also has `algorithm` (its menu key) and `params` (the form's, as JSON). A tile job (`kind:
/// "tile"`) has `config` (the catalogue's [`Config`](crate::catalogue::Config) as JSON), `plan`
/// (the tile plan as JSON), `tile`, `seed` (decimal text: a seed may exceed what a JavaScript
/// number holds exactly) and `members` (how many of its optimizer's members the tile's front
/// keeps).
pub(super) fn job_to_js(
    job: &Job,
    hf: &Heightfield,
    plan: Option<&TilePlan>,
) -> Result<JsValue, JsValue> {
    let o = Object::new();
    set(&o, "run", &JsValue::from_f64(job.run as f64))?;
    set(&o, "index", &JsValue::from_f64(job.index as f64))?;
    match &job.work {
        Work::Whole { algorithm, params } => {
            set(&o, "kind", &"whole".into())?;
            set(&o, "algorithm", &algorithm.name().into())?;
            set(&o, "params", &json(params)?.into())?;
            set(&o, "surface", &transfer::surface_to_js(hf)?)?;
        }
        Work::Tile(tile) => {
            let plan = plan.ok_or("a tile job without a plan")?;
            let cut = plan.cut(hf, tile.tile).map_err(|e| e.to_string())?;
            set(&o, "kind", &"tile".into())?;
            set(&o, "config", &json(&tile.config)?.into())?;
            set(&o, "plan", &json(plan)?.into())?;
            set(&o, "tile", &JsValue::from_f64(tile.tile as f64))?;
            set(&o, "seed", &tile.seed.to_string().into())?;
            set(&o, "members", &JsValue::from_f64(tile.members as f64))?;
            set(&o, "surface", &transfer::surface_to_js(&cut)?)?;
        }
    }
    Ok(o.into())
}

/// Runs tile `tile` of the plan `plan` (JSON) on its grid `surface` with `config` (the
/// catalogue's [`Config`] as JSON) and `seed`, keeping `members` members, and returns the
/// tile's front as JSON: the worker's side of a tile job, the same function a tiled CLI run
/// calls for each tile.
pub(super) fn run_tile(
    surface: &JsValue,
    plan: &str,
    tile: usize,
    config: &str,
    seed: &str,
    members: usize,
) -> Result<String, String> {
    let seed: u64 = seed.parse().map_err(|_| format!("bad seed {seed}"))?;
    let hf = transfer::surface_from_js(surface)?;
    let plan: TilePlan = serde_json::from_str(plan).map_err(|e| format!("bad tile plan: {e}"))?;
    let config: Config = serde_json::from_str(config).map_err(|e| format!("bad method: {e}"))?;
    let front = tiling::run_tile_keeping(&hf, &plan, tile, &config, seed, members)
        .map_err(|e| e.to_string())?;
    serde_json::to_string(&front).map_err(|e| e.to_string())
}

/// `front` as `{scores, offsets, kept}` ([`FrontParts`] as typed arrays).
pub(super) fn front_to_js(front: &Front) -> Result<JsValue, JsValue> {
    let parts = FrontParts::of(front);
    let o = Object::new();
    set(&o, "scores", &Float64Array::from(&parts.scores[..]).into())?;
    set(&o, "offsets", &Uint32Array::from(&parts.offsets[..]).into())?;
    set(&o, "kept", &Uint32Array::from(&parts.kept[..]).into())?;
    Ok(o.into())
}

/// The front a worker posted as [`front_to_js`]'s arrays, checked.
pub(super) fn front_from_arrays(
    scores: Vec<f64>,
    offsets: Vec<u32>,
    kept: Vec<u32>,
) -> Result<Front, String> {
    FrontParts {
        scores,
        offsets,
        kept,
    }
    .into_front()
}

/// One job running in a worker: the chosen algorithm on the job's grid, advanced in slices of
/// wall time so the worker can post its front as it grows.
pub(super) struct JobRunner {
    optimizer: Box<dyn Running>,
    /// Evaluations per step call, adapted so a call takes about a tenth of a slice.
    chunk: u64,
}

impl JobRunner {
    /// Builds `algorithm` (its menu key) with `params` (JSON) on the grid `surface` (in
    /// [`transfer`]'s form).
    pub(super) fn new(surface: &JsValue, algorithm: &str, params: &str) -> Result<Self, String> {
        let hf = transfer::surface_from_js(surface)?;
        let algorithm = Algorithm::from_name(algorithm)
            .ok_or_else(|| format!("unknown algorithm {algorithm}"))?;
        let params: Params =
            serde_json::from_str(params).map_err(|e| format!("bad parameters: {e}"))?;
        Ok(Self {
            optimizer: algorithms::build(algorithm, &params, std::sync::Arc::new(hf))?,
            chunk: 1,
        })
    }

    /// Steps for about `ms` milliseconds of wall time (at least one call) or until done.
    /// Slicing never changes a run's result, so the front is the one a run on the page reaches.
    pub(super) fn run_for(&mut self, ms: f64) -> Progress {
        let start = js_sys::Date::now();
        loop {
            let before = self.optimizer.progress().evaluations;
            let call = js_sys::Date::now();
            let p = self.optimizer.step(self.chunk);
            let now = js_sys::Date::now();
            let spent = p.evaluations - before;
            if spent > 0 {
                let per_eval = ((now - call) / spent as f64).max(1e-3);
                let target = (ms / 10.0 / per_eval).floor();
                self.chunk = target.clamp(1.0, 2.0 * self.chunk as f64) as u64;
            }
            if p.done || now - start >= ms {
                return p;
            }
        }
    }

    /// The job's front so far.
    pub(super) fn front(&self) -> &Front {
        self.optimizer.front()
    }
}

/// The status line's note on a pool run (its jobs or tiles and workers), and its failure under
/// the form.
pub(super) fn note_status(ui: &mut super::page::Ui, status: &mut String) {
    let workers = ui.app.pool_setup().workers;
    let Some(run) = ui.app.pool_run() else {
        return;
    };
    let workers = workers.min(run.job_count());
    if let Some(failure) = run.failure() {
        status.push_str(" · stopped: a worker failed");
        let failure = failure.to_string();
        super::dom::set_text("run-message", &failure);
        return;
    }
    match run.tiled() {
        Some(tiled) => {
            let tiles = tiled.plan().len();
            status.push_str(&format!(
                " · {} tiles ({}×{}) in {workers} Web Workers: {} with a front, {} final",
                tiles,
                tiled.plan().columns(),
                tiled.plan().rows(),
                tiled.tiles_reported(),
                tiled.tiles_final(),
            ));
            if tiled.assembled().is_none() {
                status.push_str(" · the whole-grid front shows once every tile has one");
            }
        }
        None => status.push_str(&format!(
            " · {} of {} jobs done in {workers} Web Workers",
            run.jobs_done(),
            run.job_count(),
        )),
    }
}
