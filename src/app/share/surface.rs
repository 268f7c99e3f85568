//! How a surface travels in a link: a built-in's name, a file's fingerprint (with the import
//! choice of a mesh that is not a grid), or the grid itself with its geometry.

use super::error::clip;
use super::wire::check_grid_size;
use super::*;
use crate::heightfield::{Georeference, Heightfield, MAX_SIDE, Placement};

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
    /// The import options this choice stands for (as `paretomesh run` would be given them),
    /// for the front.json the app writes.
    pub fn options(&self) -> Result<crate::import::ImportOptions, String> {
        let mut options = loader::options(&self.projection, self.width, self.height)?;
        if let Some(surface) = self.surface.as_deref() {
            options.surface = loader::surface(surface)?;
        }
        Ok(options)
    }

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
}

/// 64-bit FNV-1a (offset basis 0xcbf29ce484222325, prime 0x100000001b3): a fast
/// non-cryptographic hash, enough to tell a wrong file from the right one.
pub(crate) fn fnv1a64(bytes: &[u8]) -> u64 {
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

    pub(super) fn validate(&self) -> Result<(), ShareError> {
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

/// Heights of `hf` as the f32 an embedded grid carries, and whether that is exact.
pub(crate) fn embeddable(hf: &Heightfield) -> Option<(Vec<f32>, bool)> {
    if hf.width() > MAX_EMBEDDED_SIDE || hf.height() > MAX_EMBEDDED_SIDE {
        return None;
    }
    let z: Vec<f32> = hf.z().iter().map(|&v| v as f32).collect();
    let exact = z.iter().zip(hf.z()).all(|(&a, &b)| f64::from(a) == b);
    Some((z, exact))
}
