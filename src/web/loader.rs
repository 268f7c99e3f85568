//! Turning dropped files into a height field, and the built-in surface.

use crate::heightfield::{Heightfield, ImportError, raw};

/// Name of the built-in surface shown on first load.
pub const BUILTIN_NAME: &str = "jacksboro_65x65";
const BUILTIN_GRID: &[u8] = include_bytes!("../../tests/data/jacksboro_65x65.f32");
const BUILTIN_SIDECAR: &[u8] = include_bytes!("../../tests/data/jacksboro_65x65.json");

/// The built-in surface: the Jacksboro fault DEM, 65×65 (see tests/data/SOURCES.md).
pub fn builtin() -> Heightfield {
    raw::parse(BUILTIN_GRID, BUILTIN_SIDECAR, BUILTIN_NAME)
        .expect("the built-in surface is a valid grid (tested)")
}

/// Lower-case extension of a file name ("" when none).
pub fn extension(name: &str) -> String {
    name.rsplit_once('.')
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default()
}

/// Parses a dropped file `name` with `bytes`; `.f32` grids need their `.json` `sidecar`.
pub fn parse(name: &str, bytes: &[u8], sidecar: Option<&[u8]>) -> Result<Heightfield, String> {
    match extension(name).as_str() {
        "f32" => {
            let json = sidecar.ok_or_else(|| {
                format!("{name}: a .f32 grid needs its .json sidecar; drop both files together")
            })?;
            raw::parse(bytes, json, name).map_err(|e| format!("{name}: {e}"))
        }
        _ => Err(ImportError::UnknownFormat {
            name: name.to_string(),
        }
        .to_string()),
    }
}
