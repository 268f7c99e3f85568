//! The link's wire format: the JSON fields, base64 and the deflated grid, both ways.

use super::error::clip;
use super::*;
use crate::heightfield::{Georeference, Placement};
use base64::Engine;
use base64::engine::general_purpose::URL_SAFE_NO_PAD;

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
    #[serde(default, skip_serializing_if = "Option::is_none")]
    epsg: Option<u16>,
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
                epsg: geo.epsg,
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
                epsg: geo.epsg,
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
        algorithm: link.algorithm.name().to_string(),
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

    let algorithm = Algorithm::from_name(&wire.algorithm)
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

pub(super) fn parse_hash(hex: &str) -> Result<u64, ShareError> {
    if hex.len() != 16 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(ShareError::BadFingerprint(format!(
            "the hash must be 16 hex digits, got \"{}\"",
            clip(hex, 20)
        )));
    }
    u64::from_str_radix(hex, 16).map_err(|e| ShareError::BadFingerprint(e.to_string()))
}

pub(super) fn check_grid_size(width: usize, height: usize) -> Result<(), ShareError> {
    let side = 2..=MAX_EMBEDDED_SIDE;
    if !side.contains(&width) || !side.contains(&height) {
        return Err(ShareError::BadGridSize { width, height });
    }
    Ok(())
}

/// Inflates the grid part of a `width`×`height` grid (sides already checked), stopping as soon
/// as the output would exceed the bytes the dimensions allow.
pub(super) fn inflate_grid(
    data: &str,
    width: usize,
    height: usize,
) -> Result<Vec<f32>, ShareError> {
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
