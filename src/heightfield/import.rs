//! Loading a height field from a file: dispatch on the file's kind, and the import error.

use super::{Heightfield, HeightfieldError, raw};
use std::fmt;
use std::path::Path;

/// Why a file could not become a height field. The message is for the user.
#[derive(Debug)]
pub enum ImportError {
    /// The file could not be read.
    Io { path: String, message: String },
    /// The file's kind is not one ParetoMesh reads.
    UnknownFormat { name: String },
    /// The file is not valid for its format.
    Malformed {
        format: &'static str,
        message: String,
    },
    /// The resulting grid is not a valid height field.
    Grid(HeightfieldError),
}

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, message } => write!(f, "cannot read {path}: {message}"),
            Self::UnknownFormat { name } => write!(
                f,
                "{name}: unknown file type; ParetoMesh reads .f32 (with a .json sidecar), .png, .ply, .obj and .stl"
            ),
            Self::Malformed { format, message } => write!(f, "invalid {format} file: {message}"),
            Self::Grid(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for ImportError {}

impl From<HeightfieldError> for ImportError {
    fn from(e: HeightfieldError) -> Self {
        Self::Grid(e)
    }
}

fn read(path: &Path) -> Result<Vec<u8>, ImportError> {
    std::fs::read(path).map_err(|e| ImportError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// Loads any supported file by its extension. A `.f32` grid reads its `.json` sidecar beside it.
pub fn load(path: &Path) -> Result<Heightfield, ImportError> {
    let name = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "f32" => {
            let sidecar = path.with_extension("json");
            let json = read(&sidecar)?;
            let data = read(path)?;
            raw::parse(&data, &json, &name)
        }
        _ => Err(ImportError::UnknownFormat { name }),
    }
}
