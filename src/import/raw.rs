//! The raw grid format of the shared data: little-endian f32, row-major, index = y·W + x, with a
//! JSON sidecar that holds at least `width` and `height`.

use super::error::ImportError;
use crate::heightfield::Heightfield;
use serde::Deserialize;

#[derive(Deserialize)]
struct Sidecar {
    width: usize,
    height: usize,
    #[serde(default)]
    source: Option<String>,
    #[serde(default)]
    units: Option<String>,
    #[serde(default)]
    derivation: Option<String>,
    #[serde(default)]
    spacing: Option<[f64; 2]>,
}

fn malformed(message: impl Into<String>) -> ImportError {
    ImportError::Malformed {
        format: "raw f32 grid",
        message: message.into(),
    }
}

/// What the sidecar of a raw grid says: its size, its source note and its spacing.
pub(super) struct RawHeader {
    pub width: usize,
    pub height: usize,
    pub note: String,
    pub spacing: Option<[f64; 2]>,
}

/// Reads the sidecar `json` of the raw grid `name`. The size is not checked here.
pub(super) fn header(json: &[u8], name: &str) -> Result<RawHeader, ImportError> {
    let meta: Sidecar =
        serde_json::from_slice(json).map_err(|e| malformed(format!("sidecar JSON: {e}")))?;
    let mut note = format!("raw f32 grid {name}");
    for part in [
        &meta.source,
        &meta.units.as_ref().map(|u| format!("units: {u}")),
        &meta.derivation,
    ]
    .into_iter()
    .flatten()
    {
        note.push_str("; ");
        note.push_str(part);
    }
    Ok(RawHeader {
        width: meta.width,
        height: meta.height,
        note,
        spacing: meta.spacing,
    })
}

/// Checks that a raw grid of `width`×`height` has exactly `len` bytes.
pub(super) fn check_length(width: usize, height: usize, len: u64) -> Result<(), ImportError> {
    let expected = (width as u64)
        .saturating_mul(height as u64)
        .saturating_mul(4);
    let grid = format!("a {width}×{height} grid needs {expected} bytes");
    if len < expected {
        return Err(ImportError::Truncated {
            format: "raw f32 grid",
            message: format!("{grid}, the file has {len}"),
        });
    }
    if len > expected {
        return Err(ImportError::WrongCount {
            format: "raw f32 grid",
            message: format!(
                "{grid}, the file has {len}; do the sidecar's width and height match the file?"
            ),
        });
    }
    Ok(())
}

/// Parses `data` (the .f32 bytes) with its sidecar `json`; `name` goes into the source note.
pub fn parse(data: &[u8], json: &[u8], name: &str) -> Result<Heightfield, ImportError> {
    let meta = header(json, name)?;
    crate::heightfield::check_size(meta.width, meta.height)?;
    check_length(meta.width, meta.height, data.len() as u64)?;
    let z: Vec<f64> = data
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
        .collect();
    let hf = Heightfield::new(meta.width, meta.height, z)?.with_source(meta.note);
    Ok(match meta.spacing {
        Some(s) => hf.with_geometry([0.0, 0.0], s)?,
        None => hf,
    })
}
