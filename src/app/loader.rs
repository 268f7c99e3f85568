//! Turning dropped files into a height field, and the built-in surface.

use crate::heightfield::Heightfield;
use crate::import::{ImportError, Projection, Surface};
use crate::import::{ImportOptions, raw};

/// A surface built into the app (copied from `tests/data`, see its SOURCES.md).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Builtin {
    /// Its name, as the surface menu and share links spell it.
    pub name: &'static str,
    /// What it is, for the menu.
    pub label: &'static str,
    grid: &'static [u8],
    sidecar: &'static [u8],
}

macro_rules! builtin {
    ($name:literal, $label:literal) => {
        Builtin {
            name: $name,
            label: $label,
            grid: include_bytes!(concat!("../../tests/data/", $name, ".f32")),
            sidecar: include_bytes!(concat!("../../tests/data/", $name, ".json")),
        }
    };
}

/// The built-in surfaces, the one shown on first load first: two terrains, a photo used as a
/// relief (a face among other things), and the range image of a 3-D scan.
pub(crate) const BUILTINS: [Builtin; 4] = [
    builtin!("jacksboro_65x65", "terrain: Jacksboro fault DEM"),
    builtin!("volcano_87x61", "terrain: Maunga Whau volcano"),
    builtin!("camera_65x65", "relief: the cameraman photo as heights"),
    builtin!("bunny_65x65", "range scan: the Stanford bunny"),
];

/// The most grid points one browser tab opens (4096² ≈ 16.8 M), below the library's own limit
/// ([`MAX_POINTS`](crate::heightfield::MAX_POINTS)): a 3601² DEM tile opens at its native size.
/// A GeoTIFF over it is fitted under it by area averaging and shown in the import dialog; any
/// other grid over it is refused.
pub(crate) const MAX_TAB_POINTS: usize = 1 << 24;

/// Name of the built-in surface shown on first load.
pub(crate) const BUILTIN_NAME: &str = BUILTINS[0].name;

impl Builtin {
    /// The built-in called `name`, if there is one.
    pub(crate) fn named(name: &str) -> Option<Builtin> {
        BUILTINS.into_iter().find(|b| b.name == name)
    }

    /// Its height field.
    pub(crate) fn heightfield(&self) -> Heightfield {
        raw::parse(self.grid, self.sidecar, self.name)
            .expect("the built-in surfaces are valid grids (tested)")
    }
}

/// The surface shown on first load: the Jacksboro fault DEM, 65×65 (see tests/data/SOURCES.md).
pub(crate) fn builtin() -> Heightfield {
    BUILTINS[0].heightfield()
}

/// Import options from the dialog's values: projection "auto" | "planar" | "cylindrical", and a
/// grid size where 0 × 0 means automatic. Fails on an unknown projection or half a size.
pub(crate) fn options(projection: &str, width: u32, height: u32) -> Result<ImportOptions, String> {
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
        ..ImportOptions::default()
    })
}

/// The import dialog's surface choice: "single" (a mesh must not fold) or "outer" (the
/// outermost hit at every grid point, for closed and thick meshes).
pub(crate) fn surface(name: &str) -> Result<Surface, String> {
    match name {
        "single" => Ok(Surface::Single),
        "outer" => Ok(Surface::Outer),
        other => Err(format!("unknown surface “{other}”")),
    }
}

/// Why a dropped file did not load.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LoadError {
    /// The message for the user, naming the file.
    pub message: String,
    /// The file is a mesh that folds over itself in every projection: its outer surface can
    /// still be imported, so the page offers that choice instead of only refusing.
    pub folds: bool,
}

/// Parses a dropped file `name` with `bytes`; `.f32` grids need their `.json` `sidecar`.
/// Every failure is a message for the user naming the file.
pub(crate) fn parse(
    name: &str,
    bytes: &[u8],
    sidecar: Option<&[u8]>,
    options: &ImportOptions,
) -> Result<Heightfield, String> {
    parse_file(name, bytes, sidecar, options).map_err(|e| e.message)
}

/// [`parse`], saying also whether the failure is a folding mesh (see [`LoadError::folds`]).
pub(crate) fn parse_file(
    name: &str,
    bytes: &[u8],
    sidecar: Option<&[u8]>,
    options: &ImportOptions,
) -> Result<Heightfield, LoadError> {
    if let Some((w, h)) = options
        .grid_size
        .filter(|(w, h)| w.saturating_mul(*h) > MAX_TAB_POINTS)
    {
        return Err(over_tab_cap(name, w, h));
    }
    let capped = ImportOptions {
        max_points: Some(
            options
                .max_points
                .map_or(MAX_TAB_POINTS, |m| m.min(MAX_TAB_POINTS)),
        ),
        ..options.clone()
    };
    let hf = crate::import::from_bytes(name, bytes, sidecar, &capped).map_err(|e| {
        let folds = matches!(e, ImportError::NoProjection { .. });
        let message = e.to_string();
        let message = if message.contains(name) {
            message
        } else {
            format!("{name}: {message}")
        };
        LoadError { message, folds }
    })?;
    if hf.len() > MAX_TAB_POINTS {
        return Err(over_tab_cap(name, hf.width(), hf.height()));
    }
    Ok(hf)
}

/// The refusal of a grid over [`MAX_TAB_POINTS`].
fn over_tab_cap(name: &str, width: usize, height: usize) -> LoadError {
    LoadError {
        message: format!(
            "{name}: a {width}×{height} grid has {:.1} M points; the limit for one browser tab is {:.1} M points (4096²); choose a smaller grid, or use the command line",
            width as f64 * height as f64 / 1e6,
            MAX_TAB_POINTS as f64 / 1e6
        ),
        folds: false,
    }
}

/// What the import dialog says about a GeoTIFF's georeferencing: map spacing, the map position
/// of the first tie point, the nodata value and how many cells it filled; `None` for a grid
/// read from another format.
pub(crate) fn georeference_summary(hf: &Heightfield) -> Option<String> {
    let geo = hf.georeference()?;
    let mut parts = Vec::new();
    match geo.pixel_scale {
        Some([sx, sy, _]) => parts.push(format!("pixel size {sx} × {sy} map units")),
        None => parts.push("no pixel scale (ModelPixelScale)".to_string()),
    }
    match geo.tiepoint {
        Some([i, j, _, x, y, _]) => {
            let at = if geo.pixel_is_point {
                "centre"
            } else {
                "corner"
            };
            parts.push(format!("pixel ({i}, {j}) {at} at map ({x}, {y})"))
        }
        None => parts.push("no tie point (ModelTiepoint)".to_string()),
    }
    match &geo.nodata {
        Some(text) => parts.push(format!(
            "nodata {text}: {} cells filled from their nearest valid cell",
            hf.filled()
        )),
        None => parts.push("no nodata value".to_string()),
    }
    Some(parts.join(" · "))
}
