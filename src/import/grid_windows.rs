//! A grid file read a window at a time, with the importer's values: a GeoTIFF (through
//! [`GeoTiffWindows`]) or a raw `.f32` grid, its missing cells filled as the whole-grid
//! importer fills them ([`super::fill`]). Memory follows the windows asked for, not the file:
//! what a tiled run holds of its grid is the tiles in flight.

use super::error::ImportError;
use super::fill::{Window, fill_window};
use super::geotiff::{map_geometry, planned_size, source_note};
use super::options::ImportOptions;
use super::raw;
use super::window::GeoTiffWindows;
use crate::heightfield::{Heightfield, HeightfieldError, MIN_SIDE};
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Rows per band of [`GridWindows::open`]'s scan (rounded up to whole strips or tiles).
const SCAN_ROWS: usize = 256;

/// Where the windows come from.
enum Reader {
    Tiff(Box<GeoTiffWindows<BufReader<File>>>),
    Raw(File),
}

/// A grid file whose windows are read on demand, from any thread (one read at a time).
pub struct GridWindows {
    path: PathBuf,
    /// True for a GeoTIFF, whose missing cells are filled; a raw grid has none.
    fills: bool,
    reader: Mutex<Reader>,
    width: usize,
    height: usize,
    origin: [f64; 2],
    spacing: [f64; 2],
    source: String,
    filled: usize,
}

fn io_error(path: &Path, e: std::io::Error) -> ImportError {
    ImportError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// A window inside a `width`×`height` grid, or the error saying it is not.
fn check_window(width: usize, height: usize, win: Window) -> Result<(), ImportError> {
    let inside = win.x0.checked_add(win.w).is_some_and(|e| e <= width)
        && win.y0.checked_add(win.h).is_some_and(|e| e <= height);
    if win.w == 0 || win.h == 0 || !inside {
        return Err(ImportError::Malformed {
            format: "grid",
            message: format!(
                "the window {}×{} at ({}, {}) is not inside the {width}×{height} grid",
                win.w, win.h, win.x0, win.y0
            ),
        });
    }
    Ok(())
}

impl Reader {
    /// The raw cells of `win` (NaN where missing, for a GeoTIFF).
    fn read(&mut self, path: &Path, width: usize, win: Window) -> Result<Vec<f64>, ImportError> {
        match self {
            Reader::Tiff(tiff) => tiff.read(win.x0, win.y0, win.w, win.h),
            Reader::Raw(file) => {
                let mut z = Vec::with_capacity(win.w * win.h);
                let mut row = vec![0u8; 4 * win.w];
                for y in win.y0..win.y0 + win.h {
                    let at = 4 * (y as u64 * width as u64 + win.x0 as u64);
                    file.seek(SeekFrom::Start(at))
                        .and_then(|_| file.read_exact(&mut row))
                        .map_err(|e| io_error(path, e))?;
                    z.extend(
                        row.chunks_exact(4)
                            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64),
                    );
                }
                Ok(z)
            }
        }
    }
}

impl GridWindows {
    /// Opens `path` for windows when the importer would read it at its own size: a GeoTIFF the
    /// importer does not resample, or a raw `.f32` grid. `None` for any other file, which is
    /// read whole by [`super::load_with`]. A file of more points than its 32-bit grid indices
    /// hold, or one that is not what its header says, is an error. Nothing is decoded yet;
    /// [`GridWindows::scan`] reads the file once for its source note.
    pub fn open(path: &Path, options: &ImportOptions) -> Result<Option<GridWindows>, ImportError> {
        let name = path.display().to_string();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let opened = match ext.as_deref() {
            Some("tif" | "tiff") => {
                if options.terrain_rgb {
                    return Ok(None);
                }
                let file = File::open(path).map_err(|e| io_error(path, e))?;
                let tiff = GeoTiffWindows::new(BufReader::new(file))?;
                let (w, h) = (tiff.width(), tiff.height());
                // The importer refuses a file over its limits unless told to resample it; its
                // windows are read at any size a tile plan can index.
                let resampled = match (options.grid_size, options.max_points) {
                    (None, None) => false,
                    _ => !matches!(planned_size(w, h, options), Ok(None)),
                };
                if resampled {
                    return Ok(None);
                }
                let geo = tiff.georeference().clone();
                let geometry = map_geometry(&geo, h);
                let (origin, spacing) = geometry.unwrap_or(([0.0, 0.0], [1.0, 1.0]));
                let georeferenced = geometry.is_some();
                let bigtiff = tiff.bigtiff();
                // The note's count of filled cells is set by the scan.
                let note =
                    move |filled| source_note(&name, w, h, filled, &geo, georeferenced, bigtiff);
                GridWindows {
                    path: path.to_path_buf(),
                    fills: true,
                    width: w,
                    height: h,
                    origin,
                    spacing,
                    source: note(0),
                    filled: 0,
                    reader: Mutex::new(Reader::Tiff(Box::new(tiff))),
                }
            }
            Some("f32") => {
                if options.terrain_rgb || options.grid_size.is_some() {
                    return Ok(None);
                }
                let json = std::fs::read(path.with_extension("json"))
                    .map_err(|e| io_error(&path.with_extension("json"), e))?;
                let header = raw::header(&json, &name)?;
                if header.width < MIN_SIDE || header.height < MIN_SIDE {
                    return Err(HeightfieldError::TooSmall {
                        width: header.width,
                        height: header.height,
                    }
                    .into());
                }
                let file = File::open(path).map_err(|e| io_error(path, e))?;
                let len = file.metadata().map_err(|e| io_error(path, e))?.len();
                raw::check_length(header.width, header.height, len)?;
                let spacing = header.spacing.unwrap_or([1.0, 1.0]);
                // The importer's own check of the spacing.
                Heightfield::new(2, 2, vec![0.0; 4])?.with_geometry([0.0, 0.0], spacing)?;
                GridWindows {
                    path: path.to_path_buf(),
                    fills: false,
                    width: header.width,
                    height: header.height,
                    origin: [0.0, 0.0],
                    spacing,
                    source: header.note,
                    filled: 0,
                    reader: Mutex::new(Reader::Raw(file)),
                }
            }
            _ => return Ok(None),
        };
        if opened.width.saturating_mul(opened.height) > u32::MAX as usize {
            return Err(HeightfieldError::TooLarge {
                width: opened.width,
                height: opened.height,
            }
            .into());
        }
        Ok(Some(opened))
    }

    /// Reads the whole file once, a band of rows at a time, for what the importer would say of
    /// the whole grid: how many cells are filled (the source note's count), and the errors it
    /// gives on reading (a grid with no valid cell; a raw grid with a value that is not a
    /// finite number).
    pub fn scan(mut self) -> Result<GridWindows, ImportError> {
        let (w, h) = (self.width, self.height);
        let bands = match self.reader.get_mut().unwrap_or_else(|e| e.into_inner()) {
            Reader::Tiff(tiff) => tiff.row_bands(SCAN_ROWS),
            Reader::Raw(_) => (0..h)
                .step_by(SCAN_ROWS)
                .map(|y| (y, SCAN_ROWS.min(h - y)))
                .collect(),
        };
        let mut missing = 0usize;
        // The whole grid's first non-finite raw value (the importer's NotFinite index).
        let mut first_bad: Option<usize> = None;
        for (y0, rows) in bands {
            let z = self.raw(Window {
                x0: 0,
                y0,
                w,
                h: rows,
            })?;
            missing += z.iter().filter(|v| !v.is_finite()).count();
            if let Some(i) = z.iter().position(|v| !v.is_finite()) {
                let index = y0 * w + i;
                first_bad = Some(first_bad.map_or(index, |b| b.min(index)));
            }
        }
        let reader = self.reader.get_mut().unwrap_or_else(|e| e.into_inner());
        match reader {
            Reader::Raw(_) => {
                if let Some(index) = first_bad {
                    return Err(HeightfieldError::NotFinite { index }.into());
                }
            }
            Reader::Tiff(tiff) => {
                if missing == w * h {
                    return Err(ImportError::Malformed {
                        format: "GeoTIFF",
                        message:
                            "every cell is nodata (or not a finite number); there is no height to read"
                                .into(),
                    });
                }
                let geo = tiff.georeference().clone();
                let geometry = map_geometry(&geo, h);
                self.source = source_note(
                    &self.path.display().to_string(),
                    w,
                    h,
                    missing,
                    &geo,
                    geometry.is_some(),
                    tiff.bigtiff(),
                );
                self.filled = missing;
            }
        }
        Ok(self)
    }

    fn raw(&self, win: Window) -> Result<Vec<f64>, ImportError> {
        check_window(self.width, self.height, win)?;
        self.reader
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .read(&self.path, self.width, win)
    }

    /// Columns `x0 .. x0 + w`, rows `y0 .. y0 + h` of the grid (row 0 first, as the importer
    /// orders them), row-major, with missing cells filled: bit for bit the window of the grid
    /// [`super::load_with`] makes of the whole file.
    pub fn read(&self, x0: usize, y0: usize, w: usize, h: usize) -> Result<Vec<f64>, ImportError> {
        let win = Window { x0, y0, w, h };
        check_window(self.width, self.height, win)?;
        let z = if self.fills {
            fill_window((self.width, self.height), win, |r| self.raw(r))?
        } else {
            self.raw(win)?
        };
        if let Some(i) = z.iter().position(|v| !v.is_finite()) {
            let index = (y0 + i / w) * self.width + x0 + i % w;
            return Err(HeightfieldError::NotFinite { index }.into());
        }
        Ok(z)
    }

    /// Grid width.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Grid height.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Grid coordinates of point (0, 0), as the importer sets them.
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }

    /// Grid spacing, as the importer sets it.
    pub fn spacing(&self) -> [f64; 2] {
        self.spacing
    }

    /// The importer's source note of the whole grid (its filled count once scanned).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Cells filled from their nearest valid cell, once scanned.
    pub fn filled(&self) -> usize {
        self.filled
    }
}
