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

use super::algorithms::{Algorithm, Params};
use super::camera::{MAX_DISTANCE, MAX_PITCH, MIN_DISTANCE, OrbitCamera};
use super::loader::{self, MAX_TAB_POINTS};
use crate::heightfield::{Georeference, Heightfield, MAX_SIDE, Placement};
use base64::Engine;
use base64::engine::general_purpose::URL_SAFE_NO_PAD;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Version tag that starts every link this module writes.
pub const VERSION: &str = "v1";
/// Longest link accepted, in bytes (a deflated 65×65 f32 grid fits; browsers take far longer
/// URLs, but nothing legitimate needs more).
pub const MAX_LINK_LEN: usize = 32 * 1024;
/// Largest side of an embedded grid.
pub const MAX_EMBEDDED_SIDE: usize = 65;
/// Longest surface or file name, in bytes.
pub const MAX_NAME_LEN: usize = 255;
/// Largest seed: 2⁵³ − 1, the largest integer a JavaScript number (the seed field) holds exactly.
pub const MAX_SEED: u64 = (1 << 53) - 1;
/// Most generations (or sweeps) a link may ask to re-run. A run stops at its own end anyway;
/// the cap bounds the classical methods, whose sweeps are bounded by the number of points.
pub const MAX_GENERATIONS_RUN: u64 = MAX_TAB_POINTS as u64;
/// Largest selected index: a front has at most 2N members (T < 2N on N points).
pub const MAX_SELECTED: usize = 2 * MAX_TAB_POINTS;
/// Largest file size a fingerprint may state: 4 GiB.
pub const MAX_FILE_SIZE: u64 = 1 << 32;
/// Largest |yaw| in radians (yaw accumulates while orbiting; any sane view is far below this).
pub const MAX_YAW: f32 = 1.0e6;
/// Largest |coordinate| of the camera target (the surface is normalised to unit size).
pub const MAX_TARGET: f32 = 1.0e4;
/// Largest magnitude of any number of an embedded grid's geometry (origin, spacing, placement
/// vectors, georeference). Map coordinates are far below it, and with it every grid point of an
/// embedded grid maps to a finite 3-D point.
pub const MAX_GEOMETRY: f64 = 1.0e15;
/// Longest GeoTIFF nodata text, in bytes (GDAL writes a number).
pub const MAX_NODATA_LEN: usize = 64;

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

/// Identifies a user's file without carrying it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileFingerprint {
    /// The file name.
    pub name: String,
    /// Its size in bytes.
    pub size: u64,
    /// 64-bit FNV-1a of its bytes ([`fnv1a64`]); 16 lower-case hex digits in the link.
    pub fnv1a64: u64,
    /// How the file was turned into a grid, when it is a mesh that is not one (the import
    /// dialog's choice); `None` for a file that is a grid.
    pub import: Option<ImportChoice>,
}

/// How a mesh that is not a grid became one: the import dialog's projection and the grid size
/// it gave. A link carries it so that the reader who drops the same file gets the same grid,
/// without the dialog.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImportChoice {
    /// "auto", "planar" or "cylindrical".
    pub projection: String,
    /// Grid points per row.
    pub width: u32,
    /// Grid rows.
    pub height: u32,
    /// "outer" for a folding mesh imported as its outer surface; absent for a single surface,
    /// so links of meshes that do not fold read as before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<String>,
}

impl ImportChoice {
    /// Checks the projection name and the grid size (2 to the largest side, at most the
    /// largest number of points).
    pub fn validate(&self) -> Result<(), ShareError> {
        let bad = |m: String| Err(ShareError::BadImport(m));
        if let Err(e) = loader::options(&self.projection, self.width, self.height) {
            return bad(e);
        }
        if let Some(Err(e)) = self.surface.as_deref().map(loader::surface) {
            return bad(e);
        }
        let (w, h) = (self.width as usize, self.height as usize);
        let side = 2..=MAX_SIDE;
        if !side.contains(&w) || !side.contains(&h) || w * h > MAX_TAB_POINTS {
            return bad(format!(
                "a {w}×{h} grid; sides must be 2 to {MAX_SIDE} and the grid at most {MAX_TAB_POINTS} points"
            ));
        }
        Ok(())
    }
}

impl FileFingerprint {
    /// The fingerprint of a file called `name` with contents `bytes`, read as it is (no import
    /// choice).
    pub fn of(name: &str, bytes: &[u8]) -> Self {
        Self {
            name: name.to_string(),
            size: bytes.len() as u64,
            fnv1a64: fnv1a64(bytes),
            import: None,
        }
    }

    /// True when `bytes` are the file this fingerprint describes (size and hash agree).
    pub fn matches(&self, bytes: &[u8]) -> bool {
        self.size == bytes.len() as u64 && self.fnv1a64 == fnv1a64(bytes)
    }
}

/// 64-bit FNV-1a (offset basis 0xcbf29ce484222325, prime 0x100000001b3): a fast
/// non-cryptographic hash, enough to tell a wrong file from the right one.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A small height grid carried in the link.
#[derive(Clone, Debug, PartialEq)]
pub struct EmbeddedGrid {
    /// Name shown to the user (the original file's name).
    pub name: String,
    /// Points per row, 2..=[`MAX_EMBEDDED_SIDE`].
    pub width: usize,
    /// Rows, 2..=[`MAX_EMBEDDED_SIDE`].
    pub height: usize,
    /// Heights, row-major, `width · height` finite values. f32 because that is what the raw
    /// format stores, and half the link length of f64.
    pub z: Vec<f32>,
    /// Where the grid lies: what its height field holds besides the heights.
    pub geometry: GridGeometry,
}

/// Everything of an embedded grid's height field besides its heights, so that the reader's
/// surface lies where the writer's did and exports land on the same map coordinates. The
/// default, unit spacing at the origin with nothing else, is what links without it mean.
#[derive(Clone, Debug, PartialEq)]
pub struct GridGeometry {
    /// Grid coordinates of point (0, 0) ([`Heightfield::origin`]).
    pub origin: [f64; 2],
    /// Grid spacing along x and y ([`Heightfield::spacing`]).
    pub spacing: [f64; 2],
    /// How grid coordinates map back to 3-D ([`Heightfield::placement`]).
    pub placement: Placement,
    /// Points filled from their nearest valid neighbour, e.g. a GeoTIFF's nodata cells
    /// ([`Heightfield::filled`]).
    pub filled: usize,
    /// The GeoTIFF georeferencing, for a grid read from a GeoTIFF.
    pub georeference: Option<Georeference>,
}

impl Default for GridGeometry {
    fn default() -> Self {
        Self {
            origin: [0.0, 0.0],
            spacing: [1.0, 1.0],
            placement: Placement::Grid,
            filled: 0,
            georeference: None,
        }
    }
}

impl GridGeometry {
    /// The geometry of `hf`.
    pub fn of(hf: &Heightfield) -> Self {
        Self {
            origin: hf.origin(),
            spacing: hf.spacing(),
            placement: hf.placement().clone(),
            filled: hf.filled(),
            georeference: hf.georeference().cloned(),
        }
    }

    /// Checks that every number is finite and at most [`MAX_GEOMETRY`] in magnitude, the
    /// spacing positive, the filled count at most `points`, and the nodata text short.
    pub fn validate(&self, points: usize) -> Result<(), ShareError> {
        let bad = |m: String| Err(ShareError::BadGeometry(m));
        let in_range = |values: &[f64]| values.iter().all(|v| v.abs() <= MAX_GEOMETRY);
        if !in_range(&self.origin) {
            return bad(format!(
                "the origin {:?} is not within ±{MAX_GEOMETRY:e}",
                self.origin
            ));
        }
        if !self.spacing.iter().all(|&d| d > 0.0 && d <= MAX_GEOMETRY) {
            return bad(format!(
                "the spacing {:?} is not positive and at most {MAX_GEOMETRY:e}",
                self.spacing
            ));
        }
        let vectors: Vec<f64> = match &self.placement {
            Placement::Grid => Vec::new(),
            Placement::Planar { origin, u, v, n } => [*origin, *u, *v, *n].concat(),
            Placement::Cylindrical {
                origin,
                axis,
                reference,
            } => [*origin, *axis, *reference].concat(),
        };
        if !in_range(&vectors) {
            return bad(format!(
                "a placement vector is not within ±{MAX_GEOMETRY:e}"
            ));
        }
        if self.filled > points {
            return bad(format!(
                "{} filled points on a grid of {points}",
                self.filled
            ));
        }
        if let Some(geo) = &self.georeference {
            let numbers = [
                geo.pixel_scale.as_ref().map_or(&[][..], |s| &s[..]),
                geo.tiepoint.as_ref().map_or(&[][..], |t| &t[..]),
            ]
            .concat();
            if !in_range(&numbers) {
                return bad(format!(
                    "a georeference number is not within ±{MAX_GEOMETRY:e}"
                ));
            }
            if let Some(text) = &geo.nodata
                && (text.is_empty()
                    || text.len() > MAX_NODATA_LEN
                    || text.chars().any(char::is_control))
            {
                return bad(format!(
                    "the nodata text \"{}\" is empty, longer than {MAX_NODATA_LEN} bytes, or has control characters",
                    clip(text, 20)
                ));
            }
        }
        Ok(())
    }
}

impl EmbeddedGrid {
    /// The grid of `hf` named `name`, and whether its heights are exact as f32; `None` when it
    /// is too large to embed.
    pub fn of(name: &str, hf: &Heightfield) -> Option<(Self, bool)> {
        let (z, exact) = embeddable(hf)?;
        let grid = Self {
            name: name.to_string(),
            width: hf.width(),
            height: hf.height(),
            z,
            geometry: GridGeometry::of(hf),
        };
        Some((grid, exact))
    }

    /// The grid as a height field, with its geometry. Fails as [`decode`] would on a bad size,
    /// a non-finite height or a bad geometry.
    pub fn to_heightfield(&self) -> Result<Heightfield, ShareError> {
        self.validate()?;
        let z = self.z.iter().map(|&v| f64::from(v)).collect();
        let g = &self.geometry;
        let mut hf = Heightfield::new(self.width, self.height, z)
            .and_then(|hf| hf.with_geometry(g.origin, g.spacing))
            .map_err(|e| ShareError::BadGrid(e.to_string()))?
            .with_placement(g.placement.clone())
            .with_filled(g.filled);
        if let Some(georeference) = &g.georeference {
            hf = hf.with_georeference(georeference.clone());
        }
        Ok(hf)
    }

    fn validate(&self) -> Result<(), ShareError> {
        validate_name(&self.name)?;
        check_grid_size(self.width, self.height)?;
        let expected = self.width * self.height;
        if self.z.len() != expected {
            return Err(ShareError::GridLengthMismatch {
                expected: expected * 4,
                found: self.z.len() * 4,
            });
        }
        if let Some(index) = self.z.iter().position(|v| !v.is_finite()) {
            return Err(ShareError::NonFiniteHeight { index });
        }
        self.geometry.validate(expected)
    }
}

/// Where the shown surface came from: what a share link can say about it.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// A built-in surface.
    Builtin(&'static str),
    /// A user's file, known by its fingerprint.
    File(FileFingerprint),
    /// A grid that came embedded in a link (re-sharing embeds it again).
    Embedded,
}

/// Heights of `hf` as the f32 an embedded grid carries, and whether that is exact.
pub fn embeddable(hf: &Heightfield) -> Option<(Vec<f32>, bool)> {
    if hf.width() > MAX_EMBEDDED_SIDE || hf.height() > MAX_EMBEDDED_SIDE {
        return None;
    }
    let z: Vec<f32> = hf.z().iter().map(|&v| v as f32).collect();
    let exact = z.iter().zip(hf.z()).all(|(&a, &b)| f64::from(a) == b);
    Some((z, exact))
}

/// Why a link was refused. The Display text is written for the person who opened the link.
#[derive(Clone, Debug, PartialEq)]
pub enum ShareError {
    /// The link is longer than [`MAX_LINK_LEN`].
    TooLong {
        /// Its length in bytes.
        len: usize,
    },
    /// The link does not start with a known version tag.
    UnsupportedVersion(String),
    /// A part is not URL-safe base64 (which part: "settings" or "grid").
    BadBase64(&'static str),
    /// The settings are not the expected JSON (wrong types, missing or unknown fields).
    Malformed(String),
    /// The algorithm name is not one the app has.
    UnknownAlgorithm(String),
    /// The built-in surface name is not one the app has.
    UnknownBuiltin(String),
    /// A surface or file name is empty, too long, or has control characters.
    BadName,
    /// The file fingerprint's hash is not 16 hex digits, or its size is out of range.
    BadFingerprint(String),
    /// The import choice of a file fingerprint is invalid (unknown projection, bad grid size).
    BadImport(String),
    /// The run parameters are out of range.
    InvalidParams(String),
    /// A number is out of its range or not finite (which field, and what is allowed).
    OutOfRange {
        /// The field.
        field: &'static str,
        /// What is allowed.
        allowed: String,
    },
    /// The embedded grid's sides are out of range.
    BadGridSize {
        /// Its width.
        width: usize,
        /// Its height.
        height: usize,
    },
    /// The link names an embedded grid but carries none.
    MissingGrid,
    /// The link carries grid data but its surface is not an embedded grid.
    UnexpectedGrid,
    /// The grid data inflates to more than its dimensions allow.
    GridTooLarge,
    /// The grid data is not valid deflate data.
    CorruptGrid,
    /// The grid data's byte count does not match its dimensions.
    GridLengthMismatch {
        /// Bytes the dimensions call for.
        expected: usize,
        /// Bytes found.
        found: usize,
    },
    /// A height of the grid is NaN or infinite.
    NonFiniteHeight {
        /// Its row-major index.
        index: usize,
    },
    /// The grid is not a valid height field.
    BadGrid(String),
    /// The embedded grid's geometry (origin, spacing, placement, georeference) is invalid.
    BadGeometry(String),
}

/// At most `max` characters of `s`, for echoing hostile input in a message.
fn clip(s: &str, max: usize) -> String {
    let mut out: String = s.chars().take(max).collect();
    if s.chars().nth(max).is_some() {
        out.push('…');
    }
    out
}

impl fmt::Display for ShareError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "This share link cannot be opened: ")?;
        match self {
            Self::TooLong { len } => write!(
                f,
                "it is {len} characters long, more than the {MAX_LINK_LEN} allowed."
            ),
            Self::UnsupportedVersion(v) => write!(
                f,
                "it does not start with \"{VERSION}.\" (found \"{}\"); it may come from another version of the app or be cut short.",
                clip(v, 16)
            ),
            Self::BadBase64(part) => write!(
                f,
                "its {part} part is corrupt (not URL-safe base64); it may have been cut or altered."
            ),
            Self::Malformed(m) => write!(f, "its settings are malformed ({}).", clip(m, 120)),
            Self::UnknownAlgorithm(a) => write!(
                f,
                "it names an unknown algorithm \"{}\" (known: nsga2, weighted, greedy, decimation).",
                clip(a, 40)
            ),
            Self::UnknownBuiltin(s) => write!(
                f,
                "it names an unknown built-in surface \"{}\" (known: {}).",
                clip(s, 40),
                loader::BUILTINS.map(|b| b.name).join(", ")
            ),
            Self::BadName => write!(
                f,
                "its surface name is empty, longer than {MAX_NAME_LEN} bytes, or has control characters."
            ),
            Self::BadFingerprint(m) => write!(f, "its file fingerprint is invalid: {m}."),
            Self::BadImport(m) => write!(
                f,
                "its choice of how to turn the file into a grid is invalid: {}.",
                clip(m, 120)
            ),
            Self::InvalidParams(m) => write!(f, "its run parameters are invalid: {m}."),
            Self::OutOfRange { field, allowed } => {
                write!(f, "its {field} is out of range (allowed: {allowed}).")
            }
            Self::BadGridSize { width, height } => write!(
                f,
                "its embedded grid is {width}×{height}; sides must be 2 to {MAX_EMBEDDED_SIDE}."
            ),
            Self::MissingGrid => write!(f, "it should carry a grid but has none."),
            Self::UnexpectedGrid => write!(f, "it carries grid data its surface does not use."),
            Self::GridTooLarge => write!(
                f,
                "its embedded grid inflates to more data than its dimensions allow."
            ),
            Self::CorruptGrid => write!(f, "its embedded grid data is corrupt."),
            Self::GridLengthMismatch { expected, found } => write!(
                f,
                "its embedded grid has {found} bytes where its dimensions call for {expected}."
            ),
            Self::NonFiniteHeight { index } => write!(
                f,
                "its embedded grid has a NaN or infinite height at point {index}."
            ),
            Self::BadGrid(m) => write!(f, "its embedded grid is invalid: {m}."),
            Self::BadGeometry(m) => write!(
                f,
                "its embedded grid's placement (origin, spacing or georeference) is invalid: {}.",
                clip(m, 160)
            ),
        }
    }
}

impl std::error::Error for ShareError {}

/// The settings part as it travels (the grid travels separately).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Wire {
    surface: WireSurface,
    algorithm: String,
    params: Params,
    generations_run: u64,
    selected: Option<u64>,
    camera: OrbitCamera,
    toggles: ViewToggles,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum WireSurface {
    Builtin {
        name: String,
    },
    File {
        name: String,
        size: u64,
        fnv1a64: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        import: Option<ImportChoice>,
    },
    Embedded {
        name: String,
        width: u64,
        height: u64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        geometry: Option<Box<WireGeometry>>,
    },
}

/// [`GridGeometry`] as it travels; written only when it is not the default, so links of plain
/// grids are what they were before it existed.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WireGeometry {
    origin: [f64; 2],
    spacing: [f64; 2],
    #[serde(default, skip_serializing_if = "is_zero")]
    filled: u64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    placement: Option<WirePlacement>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    georeference: Option<WireGeoreference>,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// A [`Placement`] other than `Grid` (which is the absent field).
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum WirePlacement {
    Planar {
        origin: [f64; 3],
        u: [f64; 3],
        v: [f64; 3],
        n: [f64; 3],
    },
    Cylindrical {
        origin: [f64; 3],
        axis: [f64; 3],
        reference: [f64; 3],
    },
}

/// [`Georeference`] as it travels; absent tags are absent fields.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WireGeoreference {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pixel_scale: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tiepoint: Option<[f64; 6]>,
    #[serde(default, skip_serializing_if = "is_false")]
    pixel_is_point: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    nodata: Option<String>,
}

impl WireGeometry {
    /// `None` for the default geometry, which links leave out.
    fn of(g: &GridGeometry) -> Option<Self> {
        if *g == GridGeometry::default() {
            return None;
        }
        let placement = match g.placement.clone() {
            Placement::Grid => None,
            Placement::Planar { origin, u, v, n } => {
                Some(WirePlacement::Planar { origin, u, v, n })
            }
            Placement::Cylindrical {
                origin,
                axis,
                reference,
            } => Some(WirePlacement::Cylindrical {
                origin,
                axis,
                reference,
            }),
        };
        Some(Self {
            origin: g.origin,
            spacing: g.spacing,
            filled: g.filled as u64,
            placement,
            georeference: g.georeference.clone().map(|geo| WireGeoreference {
                pixel_scale: geo.pixel_scale,
                tiepoint: geo.tiepoint,
                pixel_is_point: geo.pixel_is_point,
                nodata: geo.nodata,
            }),
        })
    }

    fn into_geometry(self) -> GridGeometry {
        let placement = match self.placement {
            None => Placement::Grid,
            Some(WirePlacement::Planar { origin, u, v, n }) => {
                Placement::Planar { origin, u, v, n }
            }
            Some(WirePlacement::Cylindrical {
                origin,
                axis,
                reference,
            }) => Placement::Cylindrical {
                origin,
                axis,
                reference,
            },
        };
        GridGeometry {
            origin: self.origin,
            spacing: self.spacing,
            placement,
            // Saturates: a count past usize is refused by the range check anyway.
            filled: usize::try_from(self.filled).unwrap_or(usize::MAX),
            georeference: self.georeference.map(|geo| Georeference {
                pixel_scale: geo.pixel_scale,
                tiepoint: geo.tiepoint,
                pixel_is_point: geo.pixel_is_point,
                nodata: geo.nodata,
            }),
        }
    }
}

/// The link's URL hash fragment (without the `#`). Infallible: a [`ShareLink`] that breaks the
/// limits is still written, and [`decode`] refuses it with the matching error.
pub fn encode(link: &ShareLink) -> String {
    let (surface, grid) = match &link.surface {
        SharedSurface::Builtin(name) => (WireSurface::Builtin { name: name.clone() }, None),
        SharedSurface::File(f) => (
            WireSurface::File {
                name: f.name.clone(),
                size: f.size,
                fnv1a64: format!("{:016x}", f.fnv1a64),
                import: f.import.clone(),
            },
            None,
        ),
        SharedSurface::Embedded(g) => {
            let bytes: Vec<u8> = g.z.iter().flat_map(|v| v.to_le_bytes()).collect();
            (
                WireSurface::Embedded {
                    name: g.name.clone(),
                    width: g.width as u64,
                    height: g.height as u64,
                    geometry: WireGeometry::of(&g.geometry).map(Box::new),
                },
                Some(miniz_oxide::deflate::compress_to_vec_zlib(&bytes, 9)),
            )
        }
    };
    let wire = Wire {
        surface,
        algorithm: link.algorithm.key().to_string(),
        params: link.params.clone(),
        generations_run: link.generations_run,
        selected: link.selected.map(|s| s as u64),
        camera: link.camera,
        toggles: link.toggles,
    };
    // Serialising plain structs of numbers, strings and bools cannot fail; NaN becomes null,
    // which decode refuses.
    let json = serde_json::to_vec(&wire).unwrap_or_default();
    let mut out = format!("{VERSION}.{}", URL_SAFE_NO_PAD.encode(json));
    if let Some(grid) = grid {
        out.push('.');
        out.push_str(&URL_SAFE_NO_PAD.encode(grid));
    }
    out
}

/// Reads a link written by [`encode`] (a leading `#` is allowed) and validates every field.
/// Never panics; its work is bounded by [`MAX_LINK_LEN`] and the grid cap.
pub fn decode(fragment: &str) -> Result<ShareLink, ShareError> {
    if fragment.len() > MAX_LINK_LEN {
        return Err(ShareError::TooLong {
            len: fragment.len(),
        });
    }
    let fragment = fragment.strip_prefix('#').unwrap_or(fragment);
    let mut parts = fragment.splitn(4, '.');
    let version = parts.next().unwrap_or("");
    if version != VERSION {
        return Err(ShareError::UnsupportedVersion(version.to_string()));
    }
    let settings = parts
        .next()
        .ok_or_else(|| ShareError::Malformed("no settings".into()))?;
    let grid_part = parts.next();
    if parts.next().is_some() {
        return Err(ShareError::Malformed("too many parts".into()));
    }
    let json = URL_SAFE_NO_PAD
        .decode(settings)
        .map_err(|_| ShareError::BadBase64("settings"))?;
    let wire: Wire =
        serde_json::from_slice(&json).map_err(|e| ShareError::Malformed(e.to_string()))?;

    let algorithm = Algorithm::from_key(&wire.algorithm)
        .ok_or_else(|| ShareError::UnknownAlgorithm(wire.algorithm.clone()))?;
    let surface = match wire.surface {
        WireSurface::Builtin { name } => {
            if grid_part.is_some() {
                return Err(ShareError::UnexpectedGrid);
            }
            SharedSurface::Builtin(name)
        }
        WireSurface::File {
            name,
            size,
            fnv1a64,
            import,
        } => {
            if grid_part.is_some() {
                return Err(ShareError::UnexpectedGrid);
            }
            SharedSurface::File(FileFingerprint {
                name,
                size,
                fnv1a64: parse_hash(&fnv1a64)?,
                import,
            })
        }
        WireSurface::Embedded {
            name,
            width,
            height,
            geometry,
        } => {
            let width = usize::try_from(width).unwrap_or(usize::MAX);
            let height = usize::try_from(height).unwrap_or(usize::MAX);
            check_grid_size(width, height)?;
            let data = grid_part.ok_or(ShareError::MissingGrid)?;
            SharedSurface::Embedded(Box::new(EmbeddedGrid {
                name,
                width,
                height,
                z: inflate_grid(data, width, height)?,
                geometry: geometry.map_or_else(GridGeometry::default, |g| g.into_geometry()),
            }))
        }
    };
    let selected = match wire.selected {
        None => None,
        Some(s) => Some(
            usize::try_from(s)
                .ok()
                .filter(|&s| s <= MAX_SELECTED)
                .ok_or_else(|| ShareError::OutOfRange {
                    field: "selected solution",
                    allowed: format!("0 to {MAX_SELECTED}"),
                })?,
        ),
    };
    let link = ShareLink {
        surface,
        algorithm,
        params: wire.params,
        generations_run: wire.generations_run,
        selected,
        camera: wire.camera,
        toggles: wire.toggles,
    };
    link.validate()?;
    Ok(link)
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

fn parse_hash(hex: &str) -> Result<u64, ShareError> {
    if hex.len() != 16 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(ShareError::BadFingerprint(format!(
            "the hash must be 16 hex digits, got \"{}\"",
            clip(hex, 20)
        )));
    }
    u64::from_str_radix(hex, 16).map_err(|e| ShareError::BadFingerprint(e.to_string()))
}

fn check_grid_size(width: usize, height: usize) -> Result<(), ShareError> {
    let side = 2..=MAX_EMBEDDED_SIDE;
    if !side.contains(&width) || !side.contains(&height) {
        return Err(ShareError::BadGridSize { width, height });
    }
    Ok(())
}

/// Inflates the grid part of a `width`×`height` grid (sides already checked), stopping as soon
/// as the output would exceed the bytes the dimensions allow.
fn inflate_grid(data: &str, width: usize, height: usize) -> Result<Vec<f32>, ShareError> {
    use miniz_oxide::inflate::{TINFLStatus, decompress_to_vec_zlib_with_limit};
    let compressed = URL_SAFE_NO_PAD
        .decode(data)
        .map_err(|_| ShareError::BadBase64("grid"))?;
    let expected = width * height * 4;
    let bytes =
        decompress_to_vec_zlib_with_limit(&compressed, expected).map_err(|e| match e.status {
            TINFLStatus::HasMoreOutput => ShareError::GridTooLarge,
            _ => ShareError::CorruptGrid,
        })?;
    if bytes.len() != expected {
        return Err(ShareError::GridLengthMismatch {
            expected,
            found: bytes.len(),
        });
    }
    let z: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    if let Some(index) = z.iter().position(|v| !v.is_finite()) {
        return Err(ShareError::NonFiniteHeight { index });
    }
    Ok(z)
}
