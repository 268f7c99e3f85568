//! What every fuzz target runs and checks, shared with the stable replay test
//! (`tests/fuzz_corpus.rs` includes this file), so that a corpus file or a crash regression is
//! replayed through exactly the code libFuzzer ran.
//!
//! Properties, beyond "no panic" (libFuzzer's memory and time limits are the other two):
//! - an error names the format of the importer that refused the input and says something;
//! - an imported grid is within the size limits, finite, and maps back to finite 3-D points;
//! - a share link that decodes is valid, re-encodes to a link that decodes to the same thing,
//!   and its embedded grid, if any, is a height field.

use paretomesh::heightfield::{Heightfield, MAX_POINTS, MAX_SIDE, MIN_SIDE};
use paretomesh::import;
use paretomesh::import::{ImportError, ImportOptions, Projection, Surface};
use paretomesh::share;

/// One fuzz target: an importer (or the share-link decoder) and the options it is run with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// Raw `.f32` grid with its JSON sidecar.
    Raw,
    /// PNG heightmap, as grayscale/luminance and as terrain-RGB.
    Png,
    /// GeoTIFF DEM, at its own size and resampled.
    Tiff,
    /// PLY mesh, ASCII and binary.
    Ply,
    /// Wavefront OBJ mesh.
    Obj,
    /// STL mesh, ASCII and binary.
    Stl,
    /// The app's share-link decoder (the URL fragment, read as UTF-8 with bad bytes replaced).
    Share,
}

impl Target {
    /// Every target, in the order the replay test reports them.
    pub const ALL: [Target; 7] = [
        Target::Raw,
        Target::Png,
        Target::Tiff,
        Target::Ply,
        Target::Obj,
        Target::Stl,
        Target::Share,
    ];

    /// The fuzz target's name: its binary in `fuzz/fuzz_targets/` and its folder under
    /// `fuzz/seeds/` and `fuzz/regressions/`.
    pub fn name(self) -> &'static str {
        match self {
            Target::Raw => "import_raw",
            Target::Png => "import_png",
            Target::Tiff => "import_tiff",
            Target::Ply => "import_ply",
            Target::Obj => "import_obj",
            Target::Stl => "import_stl",
            Target::Share => "share_link",
        }
    }

    /// The file name the input is imported under (the importer dispatches on its extension).
    pub fn file_name(self) -> &'static str {
        match self {
            Target::Raw => "fuzz.f32",
            Target::Png => "fuzz.png",
            Target::Tiff => "fuzz.tif",
            Target::Ply => "fuzz.ply",
            Target::Obj => "fuzz.obj",
            Target::Stl => "fuzz.stl",
            Target::Share => "",
        }
    }

    /// The `format` an error of this importer names.
    fn format(self) -> &'static str {
        match self {
            Target::Raw => "raw f32 grid",
            Target::Png => "PNG",
            Target::Tiff => "GeoTIFF",
            Target::Ply => "PLY",
            Target::Obj => "OBJ",
            Target::Stl => "STL",
            Target::Share => "share link",
        }
    }

    /// The option sets an input is imported with: the defaults, and the variants that take
    /// other paths through the importer.
    fn options(self) -> Vec<ImportOptions> {
        let defaults = ImportOptions::default();
        match self {
            Target::Raw => vec![defaults],
            Target::Png => vec![
                defaults,
                ImportOptions {
                    terrain_rgb: true,
                    ..Default::default()
                },
            ],
            Target::Tiff => vec![
                defaults,
                ImportOptions {
                    grid_size: Some((7, 5)),
                    ..Default::default()
                },
            ],
            Target::Share => Vec::new(),
            Target::Ply | Target::Obj | Target::Stl => vec![
                defaults,
                ImportOptions {
                    surface: Surface::Outer,
                    ..Default::default()
                },
                ImportOptions {
                    projection: Projection::Cylindrical,
                    surface: Surface::Outer,
                    grid_size: Some((12, 9)),
                    ..Default::default()
                },
            ],
        }
    }
}

/// Splits a raw-grid input into its JSON sidecar and its `.f32` bytes: a little-endian u16
/// sidecar length, the sidecar, then the grid (a length past the end takes everything).
pub fn split_raw(data: &[u8]) -> (&[u8], &[u8]) {
    if data.len() < 2 {
        return (data, &[]);
    }
    let n = usize::from(u16::from_le_bytes([data[0], data[1]]));
    data[2..].split_at(n.min(data.len() - 2))
}

/// Imports `data` as `target` with each of its option sets (or decodes it as a share link) and
/// checks the properties in the module doc; panics (a libFuzzer crash) when one fails. Returns
/// one line per option set, starting "ok" for an import or a decoded link.
pub fn run(target: Target, data: &[u8]) -> Vec<String> {
    if target == Target::Share {
        return vec![decode_share_link(data)];
    }
    let (bytes, sidecar) = match target {
        Target::Raw => {
            let (json, grid) = split_raw(data);
            (grid, Some(json))
        }
        _ => (data, None),
    };
    target
        .options()
        .iter()
        .map(
            |options| match import::from_bytes(target.file_name(), bytes, sidecar, options) {
                Ok(hf) => {
                    check_grid(&hf);
                    format!("ok {}×{}", hf.width(), hf.height())
                }
                Err(e) => {
                    check_error(target, options, &e);
                    format!("error: {e}")
                }
            },
        )
        .collect()
}

/// An error names the importer's format (when it names one) and says what is wrong in words.
fn check_error(target: Target, options: &ImportOptions, e: &ImportError) {
    let named = match e {
        ImportError::Unsupported { format, .. }
        | ImportError::Malformed { format, .. }
        | ImportError::Truncated { format, .. }
        | ImportError::WrongCount { format, .. }
        | ImportError::NotFinite { format, .. }
        | ImportError::EmptyMesh { format }
        | ImportError::OverLimit { format, .. } => Some(*format),
        ImportError::Io { .. } | ImportError::UnknownFormat { .. } => {
            panic!("{target:?}: an in-memory import gave {e:?}")
        }
        _ => None,
    };
    if let Some(format) = named {
        assert_eq!(
            format,
            target.format(),
            "{target:?} with {options:?}: the error names another format: {e}"
        );
    }
    let message = e.to_string();
    let words = message.split_whitespace().count();
    assert!(
        words >= 4,
        "{target:?} with {options:?}: the error does not say what is wrong: {message:?}"
    );
}

/// An imported grid is within the limits, its heights and spacing are finite, and its corners
/// map back to finite points (what exports write).
fn check_grid(hf: &Heightfield) {
    let (w, h) = (hf.width(), hf.height());
    assert!(
        (MIN_SIDE..=MAX_SIDE).contains(&w) && (MIN_SIDE..=MAX_SIDE).contains(&h),
        "grid {w}×{h} outside the side limits"
    );
    assert!(w * h <= MAX_POINTS, "grid {w}×{h} over the point limit");
    assert_eq!(hf.len(), w * h);
    assert!(
        hf.z().iter().all(|z| z.is_finite()),
        "a height is not finite"
    );
    let [dx, dy] = hf.spacing();
    assert!(dx > 0.0 && dy > 0.0 && dx.is_finite() && dy.is_finite());
    assert!(
        hf.origin().iter().all(|o| o.is_finite()),
        "{:?}",
        hf.origin()
    );
    for corner in hf.corners() {
        let z = hf.z()[corner as usize];
        let p = hf.to_world(corner, z);
        assert!(
            p.iter().all(|c| c.is_finite()),
            "grid point {corner} maps to {p:?} ({:?})",
            hf.placement()
        );
    }
}

/// Decodes `data` as a share link and checks what a decoded link promises.
fn decode_share_link(data: &[u8]) -> String {
    let text = String::from_utf8_lossy(data);
    match share::decode(&text) {
        Ok(link) => {
            link.validate()
                .unwrap_or_else(|e| panic!("a decoded link is invalid: {e}"));
            let again = share::encode(&link);
            // A fuzzed grid may deflate better than the encoder does; a re-encoded link over the
            // length limit is refused as such, anything else must read back the same.
            match share::decode(&again) {
                Ok(back) => assert_eq!(
                    back, link,
                    "the re-encoded link {again} reads back differently"
                ),
                Err(share::ShareError::TooLong { .. }) => {}
                Err(e) => panic!("the re-encoded link {again} does not decode: {e}"),
            }
            if let share::SharedSurface::Embedded(grid) = &link.surface {
                let hf = grid.to_heightfield().unwrap_or_else(|e| {
                    panic!("a decoded embedded grid is not a height field: {e}")
                });
                check_grid(&hf);
            }
            "ok link".to_string()
        }
        Err(e) => {
            let message = e.to_string();
            let prefix = "This share link cannot be opened: ";
            let reason = message.strip_prefix(prefix).unwrap_or_else(|| {
                panic!("a share-link error does not say it is one: {message:?}")
            });
            assert!(
                reason.split_whitespace().count() >= 4,
                "a share-link error does not say what is wrong: {message:?}"
            );
            format!("error: {message}")
        }
    }
}
