//! Library errors as Python exceptions: a file that cannot be read is an `OSError`, everything
//! else the caller can fix is a `ValueError`; both carry the CLI's message.

use paretomesh::heightfield::HeightfieldError;
use paretomesh::import::ImportError;
use pyo3::PyErr;
use pyo3::exceptions::{PyOSError, PyValueError};

/// A `ValueError` with `message`.
pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// An import failure: `OSError` when the file could not be read, else `ValueError`.
pub fn import_error(e: ImportError) -> PyErr {
    match e {
        ImportError::Io { .. } => PyOSError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// A grid that is not a height field.
pub fn grid_error(e: HeightfieldError) -> PyErr {
    PyValueError::new_err(e.to_string())
}
