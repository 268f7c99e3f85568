//! A tiled member's mesh built in a Web Worker (see [`crate::app::mesh_builds`]): the page's
//! side (the job it posts, the mesh it takes back) and the worker's side ([`MeshGrid`], which
//! holds the whole grid and triangulates a member's tile parts). `www/pool.js` runs the worker,
//! one beside the optimising ones, so a mesh never waits for a tile job to end.

use super::bindings::WebApp;
use super::costs::timed;
use super::dom;
use crate::app::mesh_builds::{MeshJob, MeshJobParts};
use crate::app::state::{ShownMesh, shown_triangles};
use crate::heightfield::Heightfield;
use crate::tiling::mesh_of_parts;
use js_sys::{Float64Array, Object, Reflect, Uint32Array};
use wasm_bindgen::prelude::*;

fn set(o: &Object, key: &str, value: &JsValue) -> Result<(), JsValue> {
    Reflect::set(o, &key.into(), value).map(|_| ())
}

/// The message the mesh worker is handed for `job`: `{id, header, kept, offsets}` (see
/// [`MeshJobParts`]) and, when the worker has not got this surface's grid yet, `grid: {width,
/// height, z}` (the page transfers the typed arrays).
fn job_to_js(job: &MeshJob, grid: Option<&Heightfield>) -> Result<JsValue, JsValue> {
    let parts = MeshJobParts::of(&job.plan, &job.parts)?;
    let o = Object::new();
    set(&o, "id", &JsValue::from_f64(job.id as f64))?;
    set(&o, "header", &parts.header.into())?;
    set(&o, "kept", &Uint32Array::from(&parts.kept[..]).into())?;
    set(&o, "offsets", &Uint32Array::from(&parts.offsets[..]).into())?;
    if let Some(hf) = grid {
        let g = Object::new();
        set(&g, "width", &JsValue::from_f64(hf.width() as f64))?;
        set(&g, "height", &JsValue::from_f64(hf.height() as f64))?;
        set(&g, "z", &Float64Array::from(hf.z()).into())?;
        set(&o, "grid", &g)?;
    }
    Ok(o.into())
}

/// The mesh a worker posted, checked against the grid `hf`: its arrays come from another
/// thread.
fn mesh_from_parts(
    hf: &Heightfield,
    kept: Vec<u32>,
    triangles: Vec<u32>,
    point_error: Vec<f64>,
    e_sum: f64,
) -> Result<ShownMesh, String> {
    let n = hf.len();
    if !triangles.len().is_multiple_of(3)
        || point_error.len() != n
        || triangles.iter().chain(&kept).any(|&i| i as usize >= n)
    {
        return Err("the mesh worker posted a mesh that does not fit the grid".to_string());
    }
    Ok(ShownMesh {
        kept,
        triangles: triangles
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
        point_error,
        e_sum,
    })
}

/// What `www/pool.js` calls to run the mesh worker.
#[wasm_bindgen]
impl WebApp {
    /// The next mesh for the mesh worker to build (see [`job_to_js`]), or null. Only the newest
    /// request waits: a selection changed twice while the worker was busy builds only the last.
    #[wasm_bindgen(js_name = takeMeshJob)]
    pub fn take_mesh_job(&self) -> Result<JsValue, JsValue> {
        let mut ui = self.ui.borrow_mut();
        let Some(job) = ui.meshes.take() else {
            return Ok(JsValue::NULL);
        };
        let hf = ui.app.surface().heightfield.clone();
        let grid = ui.meshes.send_grid().then_some(&*hf);
        timed("mesh job hand-out", || job_to_js(&job, grid))
    }

    /// The mesh worker built request `id`: its kept points, triangles (flat index triples) and
    /// error at every grid point. Drawn when it is the latest request, else dropped.
    #[wasm_bindgen(js_name = meshBuilt)]
    pub fn mesh_built(&self, id: f64, kept: Vec<u32>, triangles: Vec<u32>, point_error: Vec<f64>) {
        let mut ui = self.ui.borrow_mut();
        let Some(member) = ui.meshes.finish(id as u64) else {
            return;
        };
        let hf = ui.app.surface().heightfield.clone();
        let mesh = timed("mesh take-in", || {
            mesh_from_parts(&hf, kept, triangles, point_error, member.e_sum)
        });
        match mesh {
            Ok(mesh) => ui.shown = Some(mesh),
            Err(e) => {
                dom::show_load_message(&format!("cannot show this mesh: {e}"), true);
                ui.shown = None;
            }
        }
        timed("layers", || ui.build_layers());
        ui.selection_info();
    }

    /// The mesh worker could not build request `id`: the message shows and nothing is drawn
    /// for the selection.
    #[wasm_bindgen(js_name = meshFailed)]
    pub fn mesh_failed(&self, id: f64, message: &str) {
        let mut ui = self.ui.borrow_mut();
        if ui.meshes.finish(id as u64).is_none() {
            return;
        }
        dom::show_load_message(&format!("cannot show this mesh: {message}"), true);
        ui.shown = None;
        ui.build_layers();
        ui.selection_info();
    }

    /// The mesh worker stopped: the next job carries the grid to a new one.
    #[wasm_bindgen(js_name = meshWorkerLost)]
    pub fn mesh_worker_lost(&self) {
        self.ui.borrow_mut().meshes.grid_lost();
    }

    /// True while the selection's mesh is being built in the mesh worker.
    #[wasm_bindgen(js_name = meshBuilding)]
    pub fn mesh_building(&self) -> bool {
        self.ui.borrow().meshes.building().is_some()
    }

    /// Main-thread time per named step so far (see [`super::costs`]), as JSON; `reset` starts
    /// the tally afresh.
    #[wasm_bindgen(js_name = mainThreadCosts)]
    pub fn main_thread_costs(&self, reset: bool) -> String {
        super::costs::report(reset)
    }
}

/// The mesh worker's grid: the whole surface, sent once per surface, on which it builds the
/// meshes of tiled members.
#[wasm_bindgen]
pub struct MeshGrid {
    hf: Heightfield,
}

#[wasm_bindgen]
impl MeshGrid {
    /// The grid of `width` × `height` heights `z`.
    #[wasm_bindgen(constructor)]
    pub fn new(width: usize, height: usize, z: Vec<f64>) -> Result<MeshGrid, JsError> {
        let hf = Heightfield::new(width, height, z).map_err(|e| JsError::new(&e.to_string()))?;
        Ok(Self { hf })
    }

    /// Builds the mesh of a job's parts (`header`, `kept`, `offsets` as [`MeshJobParts`]):
    /// `{kept, triangles, pointError, eSum, eMax}` with typed arrays to transfer.
    pub fn build(
        &self,
        header: String,
        kept: Vec<u32>,
        offsets: Vec<u32>,
    ) -> Result<JsValue, JsError> {
        let err = |e: String| JsError::new(&e);
        let (plan, parts) = MeshJobParts {
            header,
            kept,
            offsets,
        }
        .unpack()
        .map_err(err)?;
        let mesh = mesh_of_parts(&plan, &self.hf, &parts).map_err(|e| err(e.to_string()))?;
        let (e_sum, e_max) = (mesh.e_sum, mesh.e_max);
        let shown = shown_triangles(&self.hf, mesh.kept, mesh.triangles, e_sum);
        let flat: Vec<u32> = shown.triangles.iter().flatten().copied().collect();
        let o = Object::new();
        let put = |key: &str, value: JsValue| {
            set(&o, key, &value).map_err(|_| JsError::new("cannot pass the mesh to the page"))
        };
        put("kept", Uint32Array::from(&shown.kept[..]).into())?;
        put("triangles", Uint32Array::from(&flat[..]).into())?;
        put(
            "pointError",
            Float64Array::from(&shown.point_error[..]).into(),
        )?;
        put("eSum", JsValue::from_f64(e_sum))?;
        put("eMax", JsValue::from_f64(e_max))?;
        Ok(o.into())
    }
}
