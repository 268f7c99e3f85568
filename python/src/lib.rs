//! `paretomesh._native`: the compiled half of the `paretomesh` Python package. The Python half
//! (`paretomesh/__init__.py`) checks and converts arguments and holds the docstrings users read;
//! this module runs the library with the GIL released.

mod errors;
mod front;
mod grid;
mod methods;
mod window;

use errors::value_error;
use front::{FrontData, GridSource, Members, PyFront, PyMember};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2, ndarray::Array2};
use paretomesh::catalogue::Algorithm;
use paretomesh::evaluator::{Evaluator, check_indices};
use paretomesh::front_file::FrontFile;
use paretomesh::front_file::GridInfo;
use paretomesh::heightfield::Heightfield;
use paretomesh::tiling::{
    TileFront, TilePlan, TiledFront, TiledFrontFile, assemble, build_optimizer, run_tiled,
    tile_params,
};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::OnceLock;
use std::time::Instant;

/// Evaluations between two looks at Python's signals (Ctrl-C) during a run: a look costs a
/// GIL round trip, and this many evaluations take a few milliseconds on small grids.
const SIGNAL_CHECK_EVALUATIONS: u64 = 250;

/// The grid note front.json keeps.
fn grid_info(hf: &Heightfield) -> GridInfo {
    GridInfo {
        width: hf.width(),
        height: hf.height(),
        source: hf.source().to_string(),
        import: None,
    }
}

/// Runs `method` untiled on `hf` to the end (looking at Python's signals between steps) and
/// returns its record.
fn run_untiled(
    hf: Arc<Heightfield>,
    method: &str,
    params: serde_json::Value,
    seed: u64,
) -> PyResult<FrontFile> {
    let mut optimizer = build_optimizer(hf.clone(), method, &params, seed)
        .map_err(|e| value_error(e.to_string()))?;
    let started = Instant::now();
    loop {
        let p = optimizer.step(SIGNAL_CHECK_EVALUATIONS);
        if p.done {
            break;
        }
        Python::attach(|py| py.check_signals())?;
    }
    let millis = started.elapsed().as_millis() as u64;
    let evaluations = optimizer.progress().evaluations;
    let mut evaluator = Evaluator::new(hf);
    FrontFile::new(
        &mut evaluator,
        method,
        params,
        seed,
        evaluations,
        millis,
        optimizer.front(),
    )
    .map_err(|e| value_error(e.to_string()))
}

/// The tile plan of a W×H grid: the given tile side, or the library's default. `None` when the
/// grid is one tile, which runs untiled.
fn plan(width: usize, height: usize, tile: Option<usize>) -> PyResult<Option<TilePlan>> {
    let plan = match tile {
        Some(t) => TilePlan::new(width, height, t),
        None => TilePlan::with_default_tile(width, height),
    }
    .map_err(|e| value_error(e.to_string()))?;
    Ok((!plan.is_single()).then_some(plan))
}

/// A tiled front's record.
fn tiled_data(
    grid: GridInfo,
    grid_source: GridSource,
    method: &str,
    params: serde_json::Value,
    seed: u64,
    millis: u64,
    front: TiledFront,
) -> FrontData {
    FrontData {
        grid_source,
        hf: OnceLock::new(),
        grid,
        algorithm: method.to_string(),
        // As the tiles ran them (the memetic search's share per tile).
        params: tile_params(&front.plan, method, &params),
        seed,
        evaluations: front.evaluations(),
        millis,
        members: Members::Tiled(front),
    }
}

/// The run behind ``paretomesh.simplify`` (see its docstring): untiled when the grid is one
/// tile, else every tile on `threads` threads (0 = every core).
#[pyfunction]
#[pyo3(signature = (z, method, seed, evals=None, threads=None, tile=None, spacing=None, origin=None, error=None))]
#[allow(clippy::too_many_arguments)]
fn simplify(
    py: Python<'_>,
    z: PyReadonlyArray2<'_, f64>,
    method: &str,
    seed: u64,
    evals: Option<u64>,
    threads: Option<usize>,
    tile: Option<usize>,
    spacing: Option<[f64; 2]>,
    origin: Option<[f64; 2]>,
    error: Option<&str>,
) -> PyResult<PyFront> {
    let params = methods::params(method, evals, error)?;
    let hf = Arc::new(grid::from_array(&z, spacing, origin)?);
    drop(z);
    let plan = plan(hf.width(), hf.height(), tile)?;
    let method = method.to_string();
    let data = py.detach(move || -> PyResult<FrontData> {
        let Some(plan) = plan else {
            let file = run_untiled(hf.clone(), &method, params, seed)?;
            return Ok(FrontData::of_file(file, GridSource::Held(hf)));
        };
        let started = Instant::now();
        let front = run_tiled(&hf, &plan, &method, &params, seed, threads.unwrap_or(0))
            .map_err(|e| value_error(e.to_string()))?;
        let millis = started.elapsed().as_millis() as u64;
        Ok(tiled_data(
            grid_info(&hf),
            GridSource::Held(hf),
            &method,
            params,
            seed,
            millis,
            front,
        ))
    })?;
    Ok(PyFront {
        data: Arc::new(data),
    })
}

/// The parameters `method` runs with for `evals` in the error measure `error`, as JSON text
/// (what Dask ships to tiles).
#[pyfunction]
#[pyo3(signature = (method, evals=None, error=None))]
fn method_params(method: &str, evals: Option<u64>, error: Option<&str>) -> PyResult<String> {
    Ok(methods::params(method, evals, error)?.to_string())
}

/// A tile's index and window: (index, x0, y0, w, h).
type TileWindow = (usize, usize, usize, usize, usize);

/// The tiles of a W×H grid: ``(tile side, [(index, x0, y0, w, h), ...])``, or an empty list
/// when the grid is one tile (it runs untiled).
#[pyfunction]
#[pyo3(signature = (width, height, tile=None))]
fn tile_plan(
    width: usize,
    height: usize,
    tile: Option<usize>,
) -> PyResult<(usize, Vec<TileWindow>)> {
    let side = tile.unwrap_or(paretomesh::tiling::DEFAULT_TILE);
    Ok(match plan(width, height, tile)? {
        None => (side, Vec::new()),
        Some(p) => (
            p.tile_size(),
            p.tiles()
                .iter()
                .map(|t| (t.index, t.x0, t.y0, t.w, t.h))
                .collect(),
        ),
    })
}

/// Runs tile `index` of the W×H grid's plan on its heights `z` and returns its front as bytes
/// (JSON), the same bits on any machine.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn run_tile<'py>(
    py: Python<'py>,
    z: PyReadonlyArray2<'_, f64>,
    width: usize,
    height: usize,
    tile: usize,
    index: usize,
    method: &str,
    params: &str,
    seed: u64,
) -> PyResult<Bound<'py, PyBytes>> {
    let tile_hf = grid::from_array(&z, None, None)?;
    drop(z);
    let params: serde_json::Value =
        serde_json::from_str(params).map_err(|e| value_error(format!("params: {e}")))?;
    let plan = TilePlan::new(width, height, tile).map_err(|e| value_error(e.to_string()))?;
    let method = method.to_string();
    let bytes = py.detach(move || -> PyResult<Vec<u8>> {
        let front = paretomesh::tiling::run_tile(&tile_hf, &plan, index, &method, &params, seed)
            .map_err(|e| value_error(e.to_string()))?;
        Ok(serde_json::to_vec(&front).expect("a tile front is plain data"))
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// Runs the whole grid `z` untiled and returns its front.json as bytes (a one-tile grid on Dask).
#[pyfunction]
fn run_whole<'py>(
    py: Python<'py>,
    z: PyReadonlyArray2<'_, f64>,
    method: &str,
    params: &str,
    seed: u64,
) -> PyResult<Bound<'py, PyBytes>> {
    let hf = Arc::new(grid::from_array(&z, None, None)?);
    drop(z);
    let params: serde_json::Value =
        serde_json::from_str(params).map_err(|e| value_error(format!("params: {e}")))?;
    let method = method.to_string();
    let bytes = py.detach(move || -> PyResult<Vec<u8>> {
        let file = run_untiled(hf, &method, params, seed)?;
        Ok(serde_json::to_vec(&file).expect("a run file is plain data"))
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// The whole-grid front from Dask's results: the tiles' fronts (bytes from ``run_tile``, in
/// any order) or one untiled front.json (bytes from ``run_whole``), with the grid as an array
/// or a file for the meshes.
#[pyfunction]
#[pyo3(signature = (width, height, tile, parts, method, params, seed, millis, source, z=None, grid_path=None, spacing=None, origin=None))]
#[allow(clippy::too_many_arguments)]
fn assemble_front(
    py: Python<'_>,
    width: usize,
    height: usize,
    tile: usize,
    parts: Vec<Vec<u8>>,
    method: &str,
    params: &str,
    seed: u64,
    millis: u64,
    source: String,
    z: Option<PyReadonlyArray2<'_, f64>>,
    grid_path: Option<PathBuf>,
    spacing: Option<[f64; 2]>,
    origin: Option<[f64; 2]>,
) -> PyResult<PyFront> {
    let grid_source = match (&z, grid_path) {
        (Some(z), _) => GridSource::Held(Arc::new(grid::from_array(z, spacing, origin)?)),
        (None, Some(path)) => GridSource::File(path),
        (None, None) => GridSource::None,
    };
    drop(z);
    let params: serde_json::Value =
        serde_json::from_str(params).map_err(|e| value_error(format!("params: {e}")))?;
    let method = method.to_string();
    let data = py.detach(move || -> PyResult<FrontData> {
        let grid = GridInfo {
            width,
            height,
            source,
            import: None,
        };
        let plan = plan(width, height, Some(tile))?;
        let Some(plan) = plan else {
            let [part] = parts.as_slice() else {
                return Err(value_error("a one-tile grid has one untiled front"));
            };
            let mut file: FrontFile = serde_json::from_slice(part)
                .map_err(|e| value_error(format!("an untiled front: {e}")))?;
            file.grid = grid;
            return Ok(FrontData::of_file(file, grid_source));
        };
        let fronts = parts
            .iter()
            .map(|b| serde_json::from_slice::<TileFront>(b))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| value_error(format!("a tile's front: {e}")))?;
        let front = assemble(&plan, fronts).map_err(|e| value_error(e.to_string()))?;
        Ok(tiled_data(
            grid,
            grid_source,
            &method,
            params,
            seed,
            millis,
            front,
        ))
    })?;
    Ok(PyFront {
        data: Arc::new(data),
    })
}

/// `z` with its nodata cells (NaN, ±inf) filled as ``simplify`` fills them, and how many.
#[pyfunction]
fn fill_nodata<'py>(
    py: Python<'py>,
    z: PyReadonlyArray2<'_, f64>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, usize)> {
    let hf = grid::from_array(&z, None, None)?;
    Ok((grid::heights(py, &hf), hf.filled()))
}

/// The grid size the importer gives the file at `path`, from its header when it can.
#[pyfunction]
fn grid_size(py: Python<'_>, path: PathBuf) -> PyResult<(usize, usize)> {
    py.detach(move || window::grid_size(&path))
        .map_err(value_error)
}

/// Grid rows ``y0 .. y0 + h`` and columns ``x0 .. x0 + w`` of the file at `path`, as the
/// importer gives them, reading only that window of a GeoTIFF when it can.
#[pyfunction]
fn read_window<'py>(
    py: Python<'py>,
    path: PathBuf,
    x0: usize,
    y0: usize,
    w: usize,
    h: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let z = py
        .detach(move || window::read(&path, x0, y0, w, h))
        .map_err(value_error)?;
    Ok(Array2::from_shape_vec((h, w), z)
        .expect("a window holds w × h values")
        .into_pyarray(py))
}

/// Reads a grid file: ``(z, georeferencing)`` (see ``paretomesh.read``).
#[pyfunction]
fn read<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyDict>)> {
    let hf = py.detach(move || grid::from_path(&path))?;
    Ok((grid::heights(py, &hf), grid::georeferencing(py, &hf)?))
}

/// Reads front.json, optionally with its grid (a file, or an array with its spacing and origin).
#[pyfunction]
#[pyo3(signature = (path, grid_path=None, z=None, spacing=None, origin=None))]
fn load_front(
    py: Python<'_>,
    path: PathBuf,
    grid_path: Option<PathBuf>,
    z: Option<PyReadonlyArray2<'_, f64>>,
    spacing: Option<[f64; 2]>,
    origin: Option<[f64; 2]>,
) -> PyResult<PyFront> {
    let from_array = match &z {
        Some(z) => Some(grid::from_array(z, spacing, origin)?),
        None => None,
    };
    drop(z);
    let data = py.detach(move || -> PyResult<FrontData> {
        let bytes = std::fs::read(&path)
            .map_err(|e| PyOSError::new_err(format!("cannot read {}: {e}", path.display())))?;
        let not_front = |e: serde_json::Error| {
            value_error(format!("{} is not a front.json: {e}", path.display()))
        };
        let value: serde_json::Value = serde_json::from_slice(&bytes).map_err(not_front)?;
        let mut data = if value.get("tiled").is_some() {
            let file: TiledFrontFile = serde_json::from_value(value).map_err(not_front)?;
            FrontData::of_tiled_file(file, GridSource::None)
        } else {
            let file: FrontFile = serde_json::from_value(value).map_err(not_front)?;
            FrontData::of_file(file, GridSource::None)
        };
        if data.len() == 0 {
            return Err(value_error(format!(
                "{} has no members in its front",
                path.display()
            )));
        }
        let hf = match (grid_path, from_array) {
            (Some(grid), _) => Some(grid::from_path(&grid)?),
            (None, Some(hf)) => Some(hf),
            (None, None) => None,
        };
        if let Some(hf) = hf {
            let (w, h) = (data.grid.width, data.grid.height);
            if (hf.width(), hf.height()) != (w, h) {
                return Err(value_error(format!(
                    "{} was made on a {w}×{h} grid, the grid given is {}×{}",
                    path.display(),
                    hf.width(),
                    hf.height()
                )));
            }
            if let Members::Untiled(members) = &data.members {
                for s in members {
                    check_indices(&s.solution.kept, hf.len())
                        .map_err(|e| value_error(e.to_string()))?;
                }
            }
            data.grid_source = GridSource::Held(Arc::new(hf));
        }
        Ok(data)
    })?;
    Ok(PyFront {
        data: Arc::new(data),
    })
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyFront>()?;
    m.add_class::<PyMember>()?;
    m.add_function(wrap_pyfunction!(simplify, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(load_front, m)?)?;
    m.add_function(wrap_pyfunction!(method_params, m)?)?;
    m.add_function(wrap_pyfunction!(tile_plan, m)?)?;
    m.add_function(wrap_pyfunction!(run_tile, m)?)?;
    m.add_function(wrap_pyfunction!(run_whole, m)?)?;
    m.add_function(wrap_pyfunction!(assemble_front, m)?)?;
    m.add_function(wrap_pyfunction!(grid_size, m)?)?;
    m.add_function(wrap_pyfunction!(fill_nodata, m)?)?;
    m.add_function(wrap_pyfunction!(read_window, m)?)?;
    m.add("METHODS", Algorithm::ALL.map(|a| a.name()).to_vec())?;
    m.add("DEFAULT_TILE", paretomesh::tiling::DEFAULT_TILE)?;
    Ok(())
}
