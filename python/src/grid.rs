//! Height fields from numpy arrays and from files, and a height field's georeferencing as a
//! Python dict.

use crate::errors::{grid_error, import_error, value_error};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2, ndarray::Array2};
use paretomesh::heightfield::{self, Heightfield, Placement};
use paretomesh::import::fill_nearest;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;

/// The importer's message for a grid with no height at all.
const NO_HEIGHT: &str = "every cell is nodata (or not a finite number); there is no height to read";

/// A height field from a 2-D array (rows = grid y, columns = grid x). NaN and infinite cells
/// are nodata and take their nearest valid cell's value, as the GeoTIFF importer fills them.
pub fn from_array(
    z: &PyReadonlyArray2<'_, f64>,
    spacing: Option<[f64; 2]>,
    origin: Option<[f64; 2]>,
) -> PyResult<Heightfield> {
    let view = z.as_array();
    let (height, width) = view.dim();
    heightfield::check_size(width, height).map_err(grid_error)?;
    let mut values: Vec<f64> = view
        .iter()
        .map(|&v| if v.is_finite() { v } else { f64::NAN })
        .collect();
    if values.iter().all(|v| v.is_nan()) {
        return Err(value_error(NO_HEIGHT));
    }
    let filled = fill_nearest(&mut values, width, height);
    let mut note = format!("numpy array ({width}×{height}");
    if filled > 0 {
        note.push_str(&format!(
            "; {filled} cells that were not finite numbers filled from their nearest valid cell"
        ));
    }
    note.push(')');
    let hf = Heightfield::new(width, height, values)
        .map_err(grid_error)?
        .with_geometry(origin.unwrap_or([0.0, 0.0]), spacing.unwrap_or([1.0, 1.0]))
        .map_err(grid_error)?;
    Ok(hf.with_filled(filled).with_source(note))
}

/// Reads any file the CLI reads, with the CLI's default import options.
pub fn from_path(path: &Path) -> PyResult<Heightfield> {
    paretomesh::import::load(path).map_err(import_error)
}

/// The heights as a (height, width) float64 array, row 0 = grid row 0.
pub fn heights<'py>(py: Python<'py>, hf: &Heightfield) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_vec((hf.height(), hf.width()), hf.z().to_vec())
        .expect("a height field holds width × height values")
        .into_pyarray(py)
}

/// The georeferencing of `hf` as a dict: ``spacing``, ``origin``, ``source``, ``filled``,
/// ``placement`` and ``geotiff`` (the GeoTIFF tags, or None).
pub fn georeferencing<'py>(py: Python<'py>, hf: &Heightfield) -> PyResult<Bound<'py, PyDict>> {
    let info = PyDict::new(py);
    let [dx, dy] = hf.spacing();
    let [x0, y0] = hf.origin();
    info.set_item("spacing", (dx, dy))?;
    info.set_item("origin", (x0, y0))?;
    info.set_item("source", hf.source())?;
    info.set_item("filled", hf.filled())?;
    let placement = PyDict::new(py);
    match hf.placement() {
        Placement::Grid => placement.set_item("kind", "grid")?,
        Placement::Planar { origin, u, v, n } => {
            placement.set_item("kind", "planar")?;
            placement.set_item("origin", origin.to_vec())?;
            placement.set_item("u", u.to_vec())?;
            placement.set_item("v", v.to_vec())?;
            placement.set_item("n", n.to_vec())?;
        }
        Placement::Cylindrical {
            origin,
            axis,
            reference,
        } => {
            placement.set_item("kind", "cylindrical")?;
            placement.set_item("origin", origin.to_vec())?;
            placement.set_item("axis", axis.to_vec())?;
            placement.set_item("reference", reference.to_vec())?;
        }
    }
    info.set_item("placement", placement)?;
    match hf.georeference() {
        None => info.set_item("geotiff", py.None())?,
        Some(geo) => {
            let tags = PyDict::new(py);
            tags.set_item("pixel_scale", geo.pixel_scale.map(|v| v.to_vec()))?;
            tags.set_item("tiepoint", geo.tiepoint.map(|v| v.to_vec()))?;
            tags.set_item("pixel_is_point", geo.pixel_is_point)?;
            tags.set_item("nodata", geo.nodata.clone())?;
            info.set_item("geotiff", tags)?;
        }
    }
    Ok(info)
}
