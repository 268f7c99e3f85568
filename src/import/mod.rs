//! Reading a file into a height field, the mirror of [`crate::export`]: one module per format,
//! the options and the error they share, and dispatch on the file's kind.
//!
//! Formats: raw `.f32` with its `.json` sidecar (`raw`), PNG heightmaps (`heightmap_png`),
//! GeoTIFF DEMs (`geotiff`), and meshes — PLY (`ply`), OBJ (`obj`), STL (`stl`) — which
//! become a grid either exactly (their vertices already form a regular grid) or by resampling
//! (`resample`). The parsers use only the leaf modules `error`, `options` and
//! `triangle_mesh`, never this dispatcher. The files are private: [`load`], [`load_with`] and
//! [`from_bytes`] read every format, with the types re-exported here.

mod error;
mod fill;
mod geotiff;
mod grid_windows;
mod heightmap_png;
mod mesh;
pub(crate) mod obj;
mod options;
pub(crate) mod ply;
pub(crate) mod raw;
mod resample;
mod stl;
mod triangle_mesh;
mod window;

pub use error::ImportError;
pub use grid_windows::GridWindows;
pub use options::{ImportOptions, Projection, Surface};
pub use resample::fill_nearest;
pub use triangle_mesh::TriangleMesh;
pub use window::{GeoTiffWindows, open_file};

/// Each format's reader by itself, for the crate's tests and fuzz harness (the `test-support`
/// feature); not part of the API.
#[cfg(feature = "test-support")]
#[doc(hidden)]
pub mod readers {
    /// Raw `.f32` grids.
    pub mod raw {
        pub use crate::import::raw::parse;
    }
    /// PLY meshes.
    pub mod ply {
        pub use crate::import::ply::parse;
    }
    /// OBJ meshes.
    pub mod obj {
        pub use crate::import::obj::parse;
    }
    /// STL meshes.
    pub mod stl {
        pub use crate::import::stl::parse;
    }
    /// A mesh to a grid.
    pub mod mesh {
        pub use crate::import::mesh::to_heightfield;
    }
}

use crate::heightfield::Heightfield;
use std::path::Path;

/// The kinds of file ParetoMesh reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Raw,
    Png,
    Tiff,
    Ply,
    Obj,
    Stl,
}

/// The kind by the name's extension (case-insensitive); for an unknown extension, by the magic
/// bytes of PNG, TIFF and PLY, the formats that have them.
fn kind_of(file_name: &str, bytes: &[u8]) -> Option<Kind> {
    let ext = Path::new(file_name)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "f32" => Some(Kind::Raw),
        "png" => Some(Kind::Png),
        "tif" | "tiff" => Some(Kind::Tiff),
        "ply" => Some(Kind::Ply),
        "obj" => Some(Kind::Obj),
        "stl" => Some(Kind::Stl),
        _ if bytes.starts_with(b"\x89PNG\r\n\x1a\n") => Some(Kind::Png),
        // Classic TIFF and BigTIFF, little- and big-endian.
        _ if [b"II*\0", b"MM\0*", b"II+\0", b"MM\0+"]
            .iter()
            .any(|m| bytes.starts_with(*m)) =>
        {
            Some(Kind::Tiff)
        }
        _ if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") => Some(Kind::Ply),
        _ => None,
    }
}

/// Parses a file given as bytes — the browser's entry point, also used by [`load_with`].
///
/// `file_name` picks the format by its extension (`.f32`, `.png`, `.tif`/`.tiff`, `.ply`,
/// `.obj`, `.stl`, case-insensitive; an unknown extension is sniffed for PNG, TIFF and PLY magic
/// bytes) and appears in the source note. A `.f32` grid needs its JSON `sidecar`; other formats ignore it. Never
/// panics: every bad input is an [`ImportError`].
pub fn from_bytes(
    file_name: &str,
    bytes: &[u8],
    sidecar: Option<&[u8]>,
    options: &ImportOptions,
) -> Result<Heightfield, ImportError> {
    let kind = kind_of(file_name, bytes).ok_or_else(|| ImportError::UnknownFormat {
        name: file_name.to_string(),
    })?;
    if options.terrain_rgb && kind != Kind::Png {
        return Err(ImportError::BadOption {
            message: format!("{file_name}: the terrain-RGB option applies to PNG files only"),
        });
    }
    match kind {
        Kind::Raw => {
            let json = sidecar.ok_or_else(|| ImportError::MissingSidecar {
                name: file_name.to_string(),
            })?;
            raw::parse(bytes, json, file_name)
        }
        Kind::Png => heightmap_png::parse(bytes, file_name, options.terrain_rgb),
        Kind::Tiff => geotiff::parse(bytes, file_name, options),
        Kind::Ply => mesh::to_heightfield(&ply::parse(bytes)?, "PLY", file_name, options),
        Kind::Obj => mesh::to_heightfield(&obj::parse(bytes)?, "OBJ", file_name, options),
        Kind::Stl => mesh::to_heightfield(&stl::parse(bytes)?, "STL", file_name, options),
    }
}

fn io_error(path: &Path, e: std::io::Error) -> ImportError {
    ImportError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

fn read(path: &Path) -> Result<Vec<u8>, ImportError> {
    std::fs::read(path).map_err(|e| io_error(path, e))
}

/// The file's first bytes, enough for [`kind_of`]'s magic numbers.
fn magic(path: &Path) -> Result<Vec<u8>, ImportError> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| io_error(path, e))?;
    let mut head = Vec::with_capacity(8);
    file.take(8)
        .read_to_end(&mut head)
        .map_err(|e| io_error(path, e))?;
    Ok(head)
}

/// Loads any supported file with the default [`ImportOptions`].
pub fn load(path: &Path) -> Result<Heightfield, ImportError> {
    load_with(path, &ImportOptions::default())
}

/// Loads any supported file by its extension; a `.f32` grid reads its `.json` sidecar beside it.
/// A GeoTIFF is decoded from the file a strip or tile at a time, never held whole in memory.
pub fn load_with(path: &Path, options: &ImportOptions) -> Result<Heightfield, ImportError> {
    let name = path.display().to_string();
    if kind_of(&name, &magic(path)?) == Some(Kind::Tiff) {
        if options.terrain_rgb {
            return Err(ImportError::BadOption {
                message: format!("{name}: the terrain-RGB option applies to PNG files only"),
            });
        }
        let file = std::fs::File::open(path).map_err(|e| io_error(path, e))?;
        return geotiff::read(std::io::BufReader::new(file), &name, options);
    }
    let data = read(path)?;
    let sidecar = match kind_of(&name, &data) {
        Some(Kind::Raw) => Some(read(&path.with_extension("json"))?),
        _ => None,
    };
    from_bytes(&name, &data, sidecar.as_deref(), options)
}
