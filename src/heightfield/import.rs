//! Loading a height field from a file or from bytes: options, dispatch on the file's kind, and
//! the import error.
//!
//! Formats: raw `.f32` with its `.json` sidecar ([`super::raw`]), PNG heightmaps
//! ([`super::heightmap_png`]), GeoTIFF DEMs ([`super::geotiff`]), and meshes — PLY ([`super::ply`]), OBJ ([`super::obj`]), STL
//! ([`super::stl`]) — which become a grid either exactly (their vertices already form a regular
//! grid) or by resampling ([`super::resample`]).

use super::{Heightfield, HeightfieldError, geotiff, heightmap_png, mesh, obj, ply, raw, stl};
use std::fmt;
use std::path::Path;

/// How a mesh that is not already a regular grid is turned into one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Projection {
    /// Use the mesh's own vertices when they form an exact regular grid in (x, y) (resampled in
    /// that plane when another grid size is asked for); otherwise a planar projection, and when
    /// that folds over itself, a cylindrical unwrap.
    #[default]
    Auto,
    /// Project onto the best-fit plane (principal component analysis of the vertices); the height
    /// is the distance along the plane's normal.
    Planar,
    /// Unwrap around the vertices' principal axis: x = angle θ, y = position ζ along the axis,
    /// z = distance ρ from the axis.
    Cylindrical,
}

impl Projection {
    /// The word used on the command line and in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Planar => "planar",
            Self::Cylindrical => "cylindrical",
        }
    }
}

/// Which surface a mesh keeps where its projection covers a grid point more than once.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Surface {
    /// The mesh must be a single surface in the projection: one that folds over itself on more
    /// than [`super::resample::MAX_OVERLAP`] of the grid is refused.
    #[default]
    Single,
    /// The outermost hit at every grid point (largest radius in a cylindrical unwrap, highest
    /// point in a planar one), like a depth map seen from outside: for closed and thick meshes.
    Outer,
}

impl Surface {
    /// The word used on the command line and in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Single => "single",
            Self::Outer => "outer",
        }
    }
}

/// Choices for turning a file into a height field. `Default` gives the documented defaults:
/// automatic projection, automatic grid size, plain grayscale PNG.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportOptions {
    /// How a mesh becomes a grid (meshes only). Default: [`Projection::Auto`].
    pub projection: Projection,
    /// Grid size `(width, height)` for resampling a mesh or a GeoTIFF. `None`: for a mesh, about
    /// as many grid points as the mesh has vertices, with the aspect ratio of the projected
    /// surface, each side capped at [`mesh::DEFAULT_MAX_SIDE`]; a GeoTIFF keeps its own size
    /// unless it is over the grid limits. With [`Projection::Auto`], a mesh whose vertices
    /// already form a grid is used as is unless a different size is asked for.
    pub grid_size: Option<(usize, usize)>,
    /// Which surface a folding mesh keeps (meshes only). Default: [`Surface::Single`].
    pub surface: Surface,
    /// Read an RGB PNG as Mapbox terrain-RGB: h = −10000 + (R·65536 + G·256 + B)·0.1.
    pub terrain_rgb: bool,
}

/// Why a file could not become a height field. The message is for the user.
#[derive(Debug)]
pub enum ImportError {
    /// The file could not be read.
    Io { path: String, message: String },
    /// The file's kind is not one ParetoMesh reads.
    UnknownFormat { name: String },
    /// A raw `.f32` grid came without its `.json` sidecar.
    MissingSidecar { name: String },
    /// The file is valid but uses something ParetoMesh does not read (a codec, several bands).
    Unsupported {
        format: &'static str,
        message: String,
    },
    /// The file is not valid for its format.
    Malformed {
        format: &'static str,
        message: String,
    },
    /// The file ends before the data its header or structure promises.
    Truncated {
        format: &'static str,
        message: String,
    },
    /// The number of elements in the file does not match what its header says.
    WrongCount {
        format: &'static str,
        message: String,
    },
    /// A coordinate or height is NaN or infinite.
    NotFinite {
        format: &'static str,
        message: String,
    },
    /// The mesh has no vertices or no triangles with area.
    EmptyMesh { format: &'static str },
    /// The header claims more elements than ParetoMesh accepts.
    OverLimit {
        format: &'static str,
        what: &'static str,
        claimed: u64,
        limit: u64,
    },
    /// The mesh folds over itself in every projection that was tried.
    NoProjection {
        /// `(projection, share of the covered grid points covered more than once)` per try;
        /// `None` when the projection has no area at all.
        tried: Vec<(Projection, Option<f64>)>,
    },
    /// Resampling the mesh would test more grid points than
    /// [`super::resample::MIN_RASTER_TESTS`] allows: many long triangles lie across each other.
    RasterLimit {
        width: usize,
        height: usize,
        limit: u64,
    },
    /// The option does not apply to this input.
    BadOption { message: String },
    /// The resulting grid is not a valid height field.
    Grid(HeightfieldError),
}

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, message } => write!(f, "cannot read {path}: {message}"),
            Self::UnknownFormat { name } => write!(
                f,
                "{name}: unknown file type; ParetoMesh reads .f32 (with a .json sidecar), .png, .tif (GeoTIFF), .ply, .obj and .stl"
            ),
            Self::MissingSidecar { name } => write!(
                f,
                "{name}: a raw .f32 grid needs its .json sidecar (with width and height) beside it"
            ),
            Self::Unsupported { format, message } => {
                write!(f, "unsupported {format} file: {message}")
            }
            Self::Malformed { format, message } => write!(f, "invalid {format} file: {message}"),
            Self::Truncated { format, message } => {
                write!(f, "the {format} file is truncated: {message}")
            }
            Self::WrongCount { format, message } => {
                write!(
                    f,
                    "the {format} file has the wrong number of elements: {message}"
                )
            }
            Self::NotFinite { format, message } => write!(
                f,
                "the {format} file has a value that is not a finite number (NaN or infinity): {message}"
            ),
            Self::EmptyMesh { format } => write!(
                f,
                "the {format} mesh is empty: it has no vertices or no triangle with any area"
            ),
            Self::OverLimit {
                format,
                what,
                claimed,
                limit,
            } => write!(
                f,
                "the {format} file claims {claimed} {what}; ParetoMesh accepts at most {limit}"
            ),
            Self::NoProjection { tried } => {
                write!(
                    f,
                    "the mesh folds over itself, so it is not a height field in any projection tried:"
                )?;
                for (i, (projection, overlap)) in tried.iter().enumerate() {
                    let sep = if i == 0 { " " } else { "; " };
                    match overlap {
                        Some(share) => write!(
                            f,
                            "{sep}{}: {:.0} % of the covered grid is covered more than once",
                            projection.name(),
                            share * 100.0
                        )?,
                        None => {
                            write!(f, "{sep}{}: the projection has no area", projection.name())?
                        }
                    }
                }
                write!(
                    f,
                    " (at most {:.0} % is accepted); a closed or thick mesh can be imported as its outer surface (--surface outer)",
                    super::resample::MAX_OVERLAP * 100.0
                )
            }
            Self::RasterLimit {
                width,
                height,
                limit,
            } => write!(
                f,
                "the mesh's triangles lie across each other so often that resampling it onto a {width}×{height} grid would test more than {limit} grid points (their bounding boxes cover the grid over {} times); a surface's triangles tile it a few times at most: remesh it into smaller triangles",
                limit / (*width as u64 * *height as u64).max(1)
            ),
            Self::BadOption { message } => write!(f, "{message}"),
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
        Kind::Tiff => geotiff::parse(bytes, file_name, options.grid_size),
        Kind::Ply => mesh::to_heightfield(&ply::parse(bytes)?, "PLY", file_name, options),
        Kind::Obj => mesh::to_heightfield(&obj::parse(bytes)?, "OBJ", file_name, options),
        Kind::Stl => mesh::to_heightfield(&stl::parse(bytes)?, "STL", file_name, options),
    }
}

fn read(path: &Path) -> Result<Vec<u8>, ImportError> {
    std::fs::read(path).map_err(|e| ImportError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// Loads any supported file with the default [`ImportOptions`].
pub fn load(path: &Path) -> Result<Heightfield, ImportError> {
    load_with(path, &ImportOptions::default())
}

/// Loads any supported file by its extension; a `.f32` grid reads its `.json` sidecar beside it.
pub fn load_with(path: &Path, options: &ImportOptions) -> Result<Heightfield, ImportError> {
    let name = path.display().to_string();
    let data = read(path)?;
    let sidecar = match kind_of(&name, &data) {
        Some(Kind::Raw) => Some(read(&path.with_extension("json"))?),
        _ => None,
    };
    from_bytes(&name, &data, sidecar.as_deref(), options)
}
