//! Why a file could not become a height field: the error every parser returns.

use super::options::{MAX_OVERLAP, Projection};
use crate::heightfield::HeightfieldError;
use std::fmt;

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
    /// Holding the grid would take more memory than the budget allows
    /// ([`ImportOptions::memory_budget`](super::ImportOptions::memory_budget)), or the
    /// allocation failed.
    OutOfMemory {
        format: &'static str,
        width: usize,
        height: usize,
        /// Bytes the grid needs.
        needed: u64,
        /// Bytes available, when known.
        available: Option<u64>,
    },
    /// The mesh folds over itself in every projection that was tried.
    NoProjection {
        /// `(projection, share of the covered grid points covered more than once)` per try;
        /// `None` when the projection has no area at all.
        tried: Vec<(Projection, Option<f64>)>,
    },
    /// Resampling the mesh would test more grid points than
    /// `super::resample::MIN_RASTER_TESTS` allows: many long triangles lie across each other.
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
            Self::OutOfMemory {
                format,
                width,
                height,
                needed,
                available,
            } => {
                let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
                write!(
                    f,
                    "the {format} grid is {width}×{height}; holding it takes {:.2} GiB",
                    gib(*needed)
                )?;
                match available {
                    Some(a) => write!(f, ", but only {:.2} GiB of memory is available", gib(*a))?,
                    None => write!(f, ", which could not be allocated")?,
                }
                write!(f, "; choose a smaller grid with the grid-size option")
            }
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
                    MAX_OVERLAP * 100.0
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
