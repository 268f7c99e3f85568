//! `paretomesh._native`: the compiled half of the `paretomesh` Python package. The Python half
//! (`paretomesh/__init__.py`) checks and converts arguments and holds the docstrings users read;
//! this module runs the library with the GIL released.

mod errors;
mod front;
mod grid;
mod methods;

use errors::{import_error, value_error};
use front::{FrontData, PyFront, PyMember};
use numpy::{PyArray2, PyReadonlyArray2};
use paretomesh::evaluator::{Evaluator, check_indices};
use paretomesh::heightfield::Heightfield;
use paretomesh::run_file::RunFile;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// Evaluations between two looks at Python's signals (Ctrl-C) during a run: a look costs a
/// GIL round trip, and this many evaluations take a few milliseconds on small grids.
const SIGNAL_CHECK_EVALUATIONS: u64 = 250;

/// Runs `method` on `hf` to the end with the GIL released, and returns its front.
fn run(hf: Arc<Heightfield>, method: &str, seed: u64, evals: Option<u64>) -> PyResult<FrontData> {
    let methods::Built {
        mut optimizer,
        params,
    } = methods::build(method, hf.clone(), seed, evals)?;
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
    let mut evaluator = Evaluator::new(hf.clone());
    let file = RunFile::new(
        &mut evaluator,
        method,
        params,
        seed,
        evaluations,
        millis,
        optimizer.front(),
    )
    .map_err(|e| value_error(e.to_string()))?;
    Ok(FrontData::of_run(hf, file))
}

/// The untiled run behind ``paretomesh.simplify`` (see its docstring).
#[pyfunction]
#[pyo3(signature = (z, method, seed, evals=None, spacing=None, origin=None))]
fn simplify(
    py: Python<'_>,
    z: PyReadonlyArray2<'_, f64>,
    method: &str,
    seed: u64,
    evals: Option<u64>,
    spacing: Option<[f64; 2]>,
    origin: Option<[f64; 2]>,
) -> PyResult<PyFront> {
    let hf = Arc::new(grid::from_array(&z, spacing, origin)?);
    drop(z);
    let method = method.to_string();
    let data = py.detach(move || run(hf, &method, seed, evals))?;
    Ok(PyFront {
        data: Arc::new(data),
    })
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
        let file: RunFile = serde_json::from_slice(&bytes)
            .map_err(|e| value_error(format!("{} is not a front.json: {e}", path.display())))?;
        if file.front.is_empty() {
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
        let mut data = FrontData::of_file(file);
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
            for s in &data.members {
                check_indices(&s.kept, hf.len()).map_err(|e| value_error(e.to_string()))?;
            }
            data.hf = Some(Arc::new(hf));
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
    m.add("METHODS", methods::METHODS.to_vec())?;
    let _ = import_error;
    Ok(())
}
