//! Share links: everything needed to reproduce a view, as a URL hash fragment, and the strict
//! validation of a link someone else wrote.
//!
//! # Format (version 1)
//!
//! `v1.<JSON>` or, with an embedded grid, `v1.<JSON>.<GRID>`, where
//! - `<JSON>` is URL-safe base64 without padding of the compact JSON of the link's fields
//!   (`surface`, `algorithm`, `params`, `generations_run`, `selected`, `camera`, `toggles`;
//!   unknown fields are rejected; a file surface made from a mesh that is not a grid also
//!   carries its `import` choice, projection and grid size, which older links simply lack;
//!   an embedded grid whose height field is not at unit spacing at the origin carries its
//!   `geometry`: origin, spacing, placement, filled-point count and GeoTIFF georeference, which
//!   links of plain grids, older ones included, lack and read as unit spacing at the origin);
//! - `<GRID>` is URL-safe base64 without padding of the zlib-deflated grid heights, f32
//!   little-endian, row-major (index = y·width + x). It travels outside the JSON so that it is
//!   base64-encoded once only.
//!
//! A leading `#` is ignored by [`decode`]. No results travel: the same seed and parameters give
//! the same front, so the reader re-runs to `generations_run`.
//!
//! # Limits
//! [`MAX_LINK_LEN`] characters in all (checked before anything is decoded), grids of at most
//! [`MAX_EMBEDDED_SIDE`]² points (inflation stops at that many bytes), names of at most
//! [`MAX_NAME_LEN`] bytes, seeds up to [`MAX_SEED`], at most [`MAX_GENERATIONS_RUN`] generations,
//! the camera within [`OrbitCamera`]'s own limits, and the run parameters as
//! [`Params::validate`] allows them. Every check is a bounded loop over a capped input, so a
//! hostile link can neither panic nor hang the page.
mod error;
mod surface;
#[cfg(test)]
mod tests;
mod wire;

pub use error::ShareError;
pub(crate) use surface::{
    EmbeddedGrid, FileFingerprint, GridGeometry, ImportChoice, embeddable, fnv1a64,
};
pub use wire::{decode, encode};

use super::algorithms::{Algorithm, Params};
use super::camera::{MAX_DISTANCE, MAX_PITCH, MIN_DISTANCE, OrbitCamera};
use super::loader;
use super::loader::MAX_TAB_POINTS;
use serde::{Deserialize, Serialize};

/// Version tag that starts every link this module writes.
pub(crate) const VERSION: &str = "v1";
/// Longest link accepted, in bytes (a deflated 65×65 f32 grid fits; browsers take far longer
/// URLs, but nothing legitimate needs more).
pub(crate) const MAX_LINK_LEN: usize = 32 * 1024;
/// Largest side of an embedded grid.
pub(crate) const MAX_EMBEDDED_SIDE: usize = 65;
/// Longest surface or file name, in bytes.
pub(crate) const MAX_NAME_LEN: usize = 255;
/// Largest seed: 2⁵³ − 1, the largest integer a JavaScript number (the seed field) holds exactly.
pub(crate) const MAX_SEED: u64 = (1 << 53) - 1;
/// Most generations (or sweeps) a link may ask to re-run. A run stops at its own end anyway;
/// the cap bounds the classical methods, whose sweeps are bounded by the number of points.
pub(crate) const MAX_GENERATIONS_RUN: u64 = MAX_TAB_POINTS as u64;
/// Largest selected index: a front has at most 2N members (T < 2N on N points).
pub(crate) const MAX_SELECTED: usize = 2 * MAX_TAB_POINTS;
/// Largest file size a fingerprint may state: 4 GiB.
pub(crate) const MAX_FILE_SIZE: u64 = 1 << 32;
/// Largest |yaw| in radians (yaw accumulates while orbiting; any sane view is far below this).
pub(crate) const MAX_YAW: f32 = 1.0e6;
/// Largest |coordinate| of the camera target (the surface is normalised to unit size).
pub(crate) const MAX_TARGET: f32 = 1.0e4;
/// Largest magnitude of any number of an embedded grid's geometry (origin, spacing, placement
/// vectors, georeference). Map coordinates are far below it, and with it every grid point of an
/// embedded grid maps to a finite 3-D point.
pub(crate) const MAX_GEOMETRY: f64 = 1.0e15;
/// Longest GeoTIFF nodata text, in bytes (GDAL writes a number).
pub(crate) const MAX_NODATA_LEN: usize = 64;

/// Everything needed to reproduce a view.
#[derive(Clone, Debug, PartialEq)]
pub struct ShareLink {
    /// The surface.
    pub surface: SharedSurface,
    /// The algorithm.
    pub algorithm: Algorithm,
    /// Its parameters, seed included.
    pub params: Params,
    /// Generations (or sweeps, for the classical methods) the run had completed.
    pub generations_run: u64,
    /// The selected solution: its index in the front sorted by T, if any.
    pub selected: Option<usize>,
    /// The camera.
    pub camera: OrbitCamera,
    /// The view toggles.
    pub toggles: ViewToggles,
}

/// What the 3-D view shows besides the selected mesh (the page's three checkboxes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewToggles {
    /// The original surface as a wireframe.
    pub original: bool,
    /// The error colouring.
    pub error: bool,
    /// The kept points.
    pub kept: bool,
}

/// Which surface a link is about.
#[derive(Clone, Debug, PartialEq)]
pub enum SharedSurface {
    /// A built-in surface, by its name (one of [`loader::BUILTINS`]).
    Builtin(String),
    /// A user's file, which the reader must drop again; the fingerprint checks it is the same.
    File(FileFingerprint),
    /// A small grid carried in the link itself (boxed: its geometry makes it the largest kind).
    Embedded(Box<EmbeddedGrid>),
}

/// Where the shown surface came from: what a share link can say about it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Origin {
    /// A built-in surface.
    Builtin(&'static str),
    /// A user's file, known by its fingerprint.
    File(FileFingerprint),
    /// A grid that came embedded in a link (re-sharing embeds it again).
    Embedded,
}

impl ShareLink {
    /// Checks every field against the limits in the module doc; [`decode`] runs it on every
    /// link it accepts.
    pub fn validate(&self) -> Result<(), ShareError> {
        match &self.surface {
            SharedSurface::Builtin(name) => {
                if loader::Builtin::named(name).is_none() {
                    return Err(ShareError::UnknownBuiltin(name.clone()));
                }
            }
            SharedSurface::File(f) => {
                validate_name(&f.name)?;
                if !(1..=MAX_FILE_SIZE).contains(&f.size) {
                    return Err(ShareError::BadFingerprint(format!(
                        "the file size must be 1 to {MAX_FILE_SIZE} bytes, got {}",
                        f.size
                    )));
                }
                if let Some(choice) = &f.import {
                    choice.validate()?;
                }
            }
            SharedSurface::Embedded(g) => g.validate()?,
        }
        if self.params.seed > MAX_SEED {
            return Err(out_of_range("seed", format!("0 to {MAX_SEED}")));
        }
        self.params.validate().map_err(ShareError::InvalidParams)?;
        if self.generations_run > MAX_GENERATIONS_RUN {
            return Err(out_of_range(
                "generation count",
                format!("0 to {MAX_GENERATIONS_RUN}"),
            ));
        }
        if self.selected.is_some_and(|s| s > MAX_SELECTED) {
            return Err(out_of_range(
                "selected solution",
                format!("0 to {MAX_SELECTED}"),
            ));
        }
        validate_camera(&self.camera)
    }
}

fn out_of_range(field: &'static str, allowed: String) -> ShareError {
    ShareError::OutOfRange { field, allowed }
}

fn validate_camera(c: &OrbitCamera) -> Result<(), ShareError> {
    // Written as `contains` so that NaN fails too.
    if !(-MAX_YAW..=MAX_YAW).contains(&c.yaw) {
        return Err(out_of_range("camera yaw", format!("±{MAX_YAW} radians")));
    }
    if !(-MAX_PITCH..=MAX_PITCH).contains(&c.pitch) {
        return Err(out_of_range(
            "camera pitch",
            format!("±{MAX_PITCH} radians"),
        ));
    }
    if !(MIN_DISTANCE..=MAX_DISTANCE).contains(&c.distance) {
        return Err(out_of_range(
            "camera distance",
            format!("{MIN_DISTANCE} to {MAX_DISTANCE}"),
        ));
    }
    if !c
        .target
        .iter()
        .all(|v| (-MAX_TARGET..=MAX_TARGET).contains(v))
    {
        return Err(out_of_range("camera target", format!("±{MAX_TARGET}")));
    }
    Ok(())
}

fn validate_name(name: &str) -> Result<(), ShareError> {
    if name.is_empty() || name.len() > MAX_NAME_LEN || name.chars().any(char::is_control) {
        return Err(ShareError::BadName);
    }
    Ok(())
}
