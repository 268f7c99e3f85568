//! Turning dropped files into a height field, and the built-in surface.

use crate::heightfield::{Heightfield, ImportOptions, import::Projection, raw};

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

/// Import options from the dialog's values: projection "auto" | "planar" | "cylindrical", and a
/// grid size where 0 × 0 means automatic. Fails on an unknown projection or half a size.
pub fn options(projection: &str, width: u32, height: u32) -> Result<ImportOptions, String> {
    let projection = match projection {
        "auto" => Projection::Auto,
        "planar" => Projection::Planar,
        "cylindrical" => Projection::Cylindrical,
        other => return Err(format!("unknown projection “{other}”")),
    };
    let grid_size = match (width, height) {
        (0, 0) => None,
        (w, h) if w > 0 && h > 0 => Some((w as usize, h as usize)),
        _ => return Err("give both grid width and height, or neither".to_string()),
    };
    Ok(ImportOptions {
        projection,
        grid_size,
        terrain_rgb: false,
    })
}

/// Parses a dropped file `name` with `bytes`; `.f32` grids need their `.json` `sidecar`.
/// Every failure is a message for the user naming the file.
pub fn parse(
    name: &str,
    bytes: &[u8],
    sidecar: Option<&[u8]>,
    options: &ImportOptions,
) -> Result<Heightfield, String> {
    crate::heightfield::import::from_bytes(name, bytes, sidecar, options).map_err(|e| {
        let message = e.to_string();
        if message.contains(name) {
            message
        } else {
            format!("{name}: {message}")
        }
    })
}
