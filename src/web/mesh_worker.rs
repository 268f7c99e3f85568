//! A tiled member's mesh built in a Web Worker (see [`crate::app::mesh_builds`]): the page's
//! side (the job it posts, the mesh it takes back) and the worker's side ([`MeshGrid`], which
//! holds the whole grid and triangulates a member's tile parts). `www/pool.js` runs the worker,
//! one beside the optimising ones, so a mesh never waits for a tile job to end.

use super::bindings::WebApp;
use super::costs::timed;
use super::dom;
use super::page::mesh_layers;
use super::style::Style;
use crate::app::geometry::{Geometry, Vertex, ViewMapping};
use crate::app::mesh_builds::{MeshJob, MeshJobParts};
use crate::app::share::ViewToggles;
use crate::app::state::{ShownMesh, shown_triangles};
use crate::heightfield::Heightfield;
use crate::tiling::mesh_of_parts;
use js_sys::{Array, Float32Array, Float64Array, Object, Reflect, Uint32Array};
use wasm_bindgen::prelude::*;

/// The view toggles as bits (original 1, error 2, kept 4), as they travel to the worker.
fn toggle_bits(t: ViewToggles) -> u32 {
    u32::from(t.original) | u32::from(t.error) << 1 | u32::from(t.kept) << 2
}

fn toggles_of(bits: u32) -> ViewToggles {
    ViewToggles {
        original: bits & 1 != 0,
        error: bits & 2 != 0,
        kept: bits & 4 != 0,
    }
}

const STYLES: [Style; 3] = [Style::Fill, Style::Lines, Style::Translucent];

/// `layers` as `[{style, vertices, indices}]` with typed arrays (vertices as floats, ten per
/// vertex), which the worker transfers.
fn layers_to_js(layers: &[(Style, Geometry)]) -> Result<JsValue, JsValue> {
    let out = Array::new();
    for (style, g) in layers {
        let o = Object::new();
        let code = STYLES.iter().position(|s| s == style).unwrap_or(0);
        set(&o, "style", &JsValue::from_f64(code as f64))?;
        let floats: &[f32] = bytemuck::cast_slice(&g.vertices);
        set(&o, "vertices", &Float32Array::from(floats).into())?;
        set(&o, "indices", &Uint32Array::from(&g.indices[..]).into())?;
        out.push(&o);
    }
    Ok(out.into())
}

/// The layers [`layers_to_js`] made, checked: they come from another thread.
fn layers_from_js(layers: &JsValue) -> Result<Vec<(Style, Geometry)>, String> {
    let bad = || "the mesh worker posted layers the page cannot read".to_string();
    let array: &Array = layers.dyn_ref().ok_or_else(bad)?;
    let per_vertex = std::mem::size_of::<Vertex>() / 4;
    array
        .iter()
        .map(|o| {
            let get = |key: &str| Reflect::get(&o, &key.into()).map_err(|_| bad());
            let style = get("style")?.as_f64().ok_or_else(bad)? as usize;
            let floats = get("vertices")?
                .dyn_into::<Float32Array>()
                .map_err(|_| bad())?
                .to_vec();
            let indices = get("indices")?
                .dyn_into::<Uint32Array>()
                .map_err(|_| bad())?
                .to_vec();
            if !floats.len().is_multiple_of(per_vertex)
                || indices
                    .iter()
                    .any(|&i| i as usize >= floats.len() / per_vertex)
            {
                return Err(bad());
            }
            let vertices: Vec<Vertex> = floats
                .chunks_exact(per_vertex)
                .map(|v| *bytemuck::from_bytes(bytemuck::cast_slice(v)))
                .collect();
            Ok((
                *STYLES.get(style).ok_or_else(bad)?,
                Geometry { vertices, indices },
            ))
        })
        .collect()
}

fn set(o: &Object, key: &str, value: &JsValue) -> Result<(), JsValue> {
    Reflect::set(o, &key.into(), value).map(|_| ())
}

/// The message the mesh worker is handed for `job`: `{id, toggles, header, kept, offsets}`
/// (see [`MeshJobParts`]; the view toggles the worker builds the 3-D layers for) and, when the worker has not got this surface's grid yet, `grid: {width,
/// height, z}` (the page transfers the typed arrays).
fn job_to_js(
    job: &MeshJob,
    grid: Option<&Heightfield>,
    toggles: ViewToggles,
) -> Result<JsValue, JsValue> {
    let parts = MeshJobParts::of(&job.plan, &job.parts)?;
    let o = Object::new();
    set(&o, "id", &JsValue::from_f64(job.id as f64))?;
    set(
        &o,
        "toggles",
        &JsValue::from_f64(toggle_bits(toggles) as f64),
    )?;
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
        let toggles = ui.toggles();
        timed("mesh job hand-out", || job_to_js(&job, grid, toggles))
    }

    /// The mesh worker built request `id`: its kept points, triangles (flat index triples),
    /// error at every grid point, and the 3-D layers for the view toggles `toggles` with the
    /// largest error `max_error`. Drawn when it is the latest request, else dropped.
    #[wasm_bindgen(js_name = meshBuilt)]
    #[allow(clippy::too_many_arguments)]
    pub fn mesh_built(
        &self,
        id: f64,
        kept: Vec<u32>,
        triangles: Vec<u32>,
        point_error: Vec<f64>,
        layers: JsValue,
        max_error: f64,
        toggles: u32,
    ) {
        let mut ui = self.ui.borrow_mut();
        let Some(member) = ui.meshes.finish(id as u64) else {
            return;
        };
        let hf = ui.app.surface().heightfield.clone();
        let mesh = timed("mesh take-in", || {
            mesh_from_parts(&hf, kept, triangles, point_error, member.e_sum)
        });
        let layers = mesh.and_then(|m| Ok((m, layers_from_js(&layers)?)));
        match layers {
            // The toggles changed while the worker built the layers: the page builds them.
            Ok((mesh, _)) if toggles_of(toggles) != ui.toggles() => {
                ui.shown = Some(mesh);
                timed("layers", || ui.build_layers());
            }
            Ok((mesh, layers)) => {
                ui.shown = Some(mesh);
                timed("layers", || ui.set_layers(layers, Some(max_error)));
            }
            Err(e) => {
                dom::show_load_message(&format!("cannot show this mesh: {e}"), true);
                ui.shown = None;
                ui.build_layers();
            }
        }
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

    /// Builds the mesh of a job's parts (`header`, `kept`, `offsets` as [`MeshJobParts`]) and
    /// its 3-D layers for the view toggles `toggles` (as bits): `{kept, triangles, pointError,
    /// eSum, eMax, maxError, layers, toggles}` with typed arrays to transfer.
    pub fn build(
        &self,
        header: String,
        kept: Vec<u32>,
        offsets: Vec<u32>,
        toggles: u32,
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
        let max_error = shown.point_error.iter().cloned().fold(0.0, f64::max);
        let map = ViewMapping::new(&self.hf);
        let layers = mesh_layers(&self.hf, &map, &shown, max_error, toggles_of(toggles));
        put("maxError", JsValue::from_f64(max_error))?;
        put(
            "layers",
            layers_to_js(&layers)
                .map_err(|_| JsError::new("cannot pass the layers to the page"))?,
        )?;
        put("toggles", JsValue::from_f64(toggles as f64))?;
        Ok(o.into())
    }
}
