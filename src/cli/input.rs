//! The input options every subcommand that reads a grid shares: the file and how to import it.

use clap::{Args, ValueEnum};
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::import::{ImportOptions, Projection, Surface};
use std::path::PathBuf;

/// How a mesh becomes a grid, as spelled on the command line.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub enum ProjectionArg {
    /// The mesh's own vertices when they form a regular grid, else planar, else cylindrical.
    #[default]
    Auto,
    /// Projection onto the best-fit plane.
    Planar,
    /// Unwrap around the principal axis (x = angle, y = along the axis, z = radius).
    Cylindrical,
}

/// Which surface of a folding mesh is kept, as spelled on the command line.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub enum SurfaceArg {
    /// The mesh must be one surface in the projection; a mesh that folds over itself is refused.
    #[default]
    Single,
    /// The outermost hit at every grid point (largest radius, or highest point): for closed and
    /// thick meshes.
    Outer,
}

/// An input grid file and its import options.
#[derive(Args, Debug)]
pub(super) struct InputArgs {
    /// Input: .f32 (with its .json sidecar), PNG, GeoTIFF (.tif), PLY, OBJ or STL.
    pub grid: PathBuf,
    /// How to import it.
    #[command(flatten)]
    pub import: ImportArgs,
}

/// How a grid file is imported; apart from the file so that a command whose grid is optional
/// (`export`) takes the same options.
#[derive(Args, Clone, Debug)]
pub(super) struct ImportArgs {
    /// How a mesh becomes a height field.
    #[arg(long, value_enum, default_value_t = ProjectionArg::Auto)]
    pub projection: ProjectionArg,
    /// Grid size WxH for resampling a mesh or a GeoTIFF, e.g. 129x129 (default: for a mesh,
    /// about one grid point per vertex, at most 257 per side; a GeoTIFF is read at its own size,
    /// up to 16384 per side and 16384² points, and as much as the machine's memory holds).
    #[arg(long, value_name = "WxH", value_parser = parse_grid_size)]
    pub grid_size: Option<(usize, usize)>,
    /// Which surface a mesh that folds over itself keeps.
    #[arg(long, value_enum, default_value_t = SurfaceArg::Single)]
    pub surface: SurfaceArg,
    /// Read an RGB PNG as Mapbox terrain-RGB: h = −10000 + (R·65536 + G·256 + B)·0.1.
    #[arg(long)]
    pub terrain_rgb: bool,
}

/// Parses `WxH` (also `W×H` or `WXH`) into two whole numbers.
fn parse_grid_size(text: &str) -> Result<(usize, usize), String> {
    let bad = || format!("grid size must look like 129x129, got {text:?}");
    let (w, h) = text.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    Ok((
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    ))
}

impl From<ProjectionArg> for Projection {
    fn from(arg: ProjectionArg) -> Self {
        match arg {
            ProjectionArg::Auto => Projection::Auto,
            ProjectionArg::Planar => Projection::Planar,
            ProjectionArg::Cylindrical => Projection::Cylindrical,
        }
    }
}

impl From<SurfaceArg> for Surface {
    fn from(arg: SurfaceArg) -> Self {
        match arg {
            SurfaceArg::Single => Surface::Single,
            SurfaceArg::Outer => Surface::Outer,
        }
    }
}

impl ImportArgs {
    /// The import options these arguments ask for.
    pub(super) fn options(&self) -> ImportOptions {
        ImportOptions {
            projection: self.projection.into(),
            grid_size: self.grid_size,
            surface: self.surface.into(),
            terrain_rgb: self.terrain_rgb,
            max_points: None,
            memory_budget: available_memory(),
        }
    }
}

/// The memory the system can give without swapping (MemAvailable in /proc/meminfo), where the
/// system says; `None` elsewhere.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Import options that change those a front.json records (`export`): each one given wins, the
/// others keep the recorded choice.
#[derive(Args, Clone, Debug)]
pub(super) struct ImportOverrides {
    /// How a mesh becomes a height field [default: as the front was made].
    #[arg(long, value_enum)]
    pub projection: Option<ProjectionArg>,
    /// Grid size WxH for resampling a mesh or a GeoTIFF [default: as the front was made].
    #[arg(long, value_name = "WxH", value_parser = parse_grid_size)]
    pub grid_size: Option<(usize, usize)>,
    /// Which surface a mesh that folds over itself keeps [default: as the front was made].
    #[arg(long, value_enum)]
    pub surface: Option<SurfaceArg>,
    /// Read an RGB PNG as Mapbox terrain-RGB [default: as the front was made].
    #[arg(long)]
    pub terrain_rgb: bool,
}

impl ImportOverrides {
    /// `recorded` with every option given here put in its place.
    pub(super) fn over(&self, recorded: ImportOptions) -> ImportOptions {
        ImportOptions {
            projection: self.projection.map_or(recorded.projection, Into::into),
            grid_size: self.grid_size.or(recorded.grid_size),
            surface: self.surface.map_or(recorded.surface, Into::into),
            terrain_rgb: self.terrain_rgb || recorded.terrain_rgb,
            ..recorded
        }
    }
}

impl InputArgs {
    /// The grid file's windows when it is read by windows at its own size (a GeoTIFF or a raw
    /// grid), not yet scanned; `None` for a file that is read whole.
    pub(super) fn windows(&self) -> Result<Option<import::GridWindows>, String> {
        import::GridWindows::open(&self.grid, &self.import.options()).map_err(|e| e.to_string())
    }

    /// Loads the grid; the error is a message for the user.
    pub(super) fn load(&self) -> Result<Heightfield, String> {
        import::load_with(&self.grid, &self.import.options()).map_err(|e| e.to_string())
    }
}
