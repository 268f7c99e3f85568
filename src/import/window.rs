//! Windows of a GeoTIFF, decoded without the rest of the file: only the strips or tiles a
//! window meets are read, one at a time, so memory follows the window, not the raster. The
//! values are the whole-image reader's ([`super::geotiff::read`]), bit for bit, because both
//! decode through one function; a missing cell (nodata, NaN or infinite) is NaN here, since
//! its fill needs cells outside the window.
//!
//! Used by the CLI's tiled runs and `tiles` (a tile's window at a time) and by the Python
//! package's Dask tasks (a window per task).

use super::error::ImportError;
use super::geotiff::{
    Chunks, Rect, chunk_layout, decode_window, georeference, map_geometry, nodata_value, open,
};
use crate::heightfield::Georeference;
use std::io::{Read, Seek, SeekFrom};
use tiff::decoder::Decoder;

/// An open single-band GeoTIFF whose windows are read on demand.
pub struct GeoTiffWindows<R: Read + Seek> {
    decoder: Decoder<R>,
    chunks: Chunks,
    width: usize,
    height: usize,
    nodata: Option<f64>,
    /// Grid row 0 is the file's last row (georeferenced files), as in the whole-image reader.
    flip: bool,
    geo: Georeference,
    /// The file is a BigTIFF (the source note says so).
    bigtiff: bool,
    /// Rows per strip or tile.
    chunk_rows: usize,
}

impl<R: Read + Seek> GeoTiffWindows<R> {
    /// Opens the file and checks its header and layout as the whole-image reader does (a
    /// strip or tile past the end of the file is [`ImportError::Truncated`]); nothing is
    /// decoded yet.
    pub fn new(mut reader: R) -> Result<Self, ImportError> {
        let io = |e: std::io::Error| ImportError::Io {
            path: "GeoTIFF".into(),
            message: e.to_string(),
        };
        let file_len = reader.seek(SeekFrom::End(0)).map_err(io)?;
        let mut magic = [0u8; 4];
        reader.seek(SeekFrom::Start(0)).map_err(io)?;
        let bigtiff = reader.read_exact(&mut magic).is_ok() && (magic[2] == 43 || magic[3] == 43);
        reader.seek(SeekFrom::Start(0)).map_err(io)?;
        let (mut decoder, width, height) = open(reader)?;
        let geo = georeference(&mut decoder)?;
        let chunks = chunk_layout(&mut decoder, width, height, file_len)?;
        let chunk_rows = chunks.rows();
        let nodata = nodata_value(&geo)?;
        let flip = map_geometry(&geo, height).is_some();
        Ok(GeoTiffWindows {
            decoder,
            chunks,
            width,
            height,
            nodata,
            flip,
            geo,
            bigtiff,
            chunk_rows,
        })
    }

    /// True for a BigTIFF.
    pub(super) fn bigtiff(&self) -> bool {
        self.bigtiff
    }

    /// Grid rows `(y0, h)` of bands that each decode whole rows of strips or tiles once, top
    /// to bottom of the file: a pass over them reads the file once.
    pub(super) fn row_bands(&self, rows_per_band: usize) -> Vec<(usize, usize)> {
        let step = rows_per_band.div_ceil(self.chunk_rows).max(1) * self.chunk_rows;
        (0..self.height)
            .step_by(step)
            .map(|f0| {
                let h = step.min(self.height - f0);
                // File rows f0 .. f0 + h are grid rows H − f0 − h .. H − f0 when turned over.
                if self.flip {
                    (self.height - f0 - h, h)
                } else {
                    (f0, h)
                }
            })
            .collect()
    }

    /// The image's width in samples.
    pub fn width(&self) -> usize {
        self.width
    }

    /// The image's height in samples.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The file's georeferencing tags.
    pub fn georeference(&self) -> &Georeference {
        &self.geo
    }

    /// Grid rows `y0 .. y0 + h` and columns `x0 .. x0 + w` (grid row 0 first, as the
    /// whole-image reader orders them), row-major; missing cells are NaN. A window that is
    /// empty or reaches outside the image is an error.
    pub fn read(
        &mut self,
        x0: usize,
        y0: usize,
        w: usize,
        h: usize,
    ) -> Result<Vec<f64>, ImportError> {
        let inside = x0.checked_add(w).is_some_and(|e| e <= self.width)
            && y0.checked_add(h).is_some_and(|e| e <= self.height);
        if w == 0 || h == 0 || !inside {
            return Err(ImportError::Malformed {
                format: "GeoTIFF",
                message: format!(
                    "the window {w}×{h} at ({x0}, {y0}) is not inside the {}×{} image",
                    self.width, self.height
                ),
            });
        }
        let mut out = Vec::new();
        out.try_reserve_exact(w * h)
            .map_err(|_| ImportError::OutOfMemory {
                format: "GeoTIFF",
                width: w,
                height: h,
                needed: 8 * (w * h) as u64,
                available: None,
            })?;
        out.resize(w * h, f64::NAN);
        decode_window(
            &mut self.decoder,
            &self.chunks,
            (self.width, self.height),
            self.nodata,
            self.flip,
            Rect { x0, y0, w, h },
            &mut out,
        )?;
        Ok(out)
    }
}

/// The windows of the GeoTIFF at `path`, or `None` when the path is not a GeoTIFF (by its
/// extension) or the importer would not read it at its own size (it resamples it): then a
/// window is only the whole grid's, read by [`super::load`].
pub fn open_file(
    path: &std::path::Path,
) -> Result<Option<GeoTiffWindows<std::io::BufReader<std::fs::File>>>, ImportError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("tif" | "tiff")) {
        return Ok(None);
    }
    let file = std::fs::File::open(path).map_err(|e| ImportError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    let windows = GeoTiffWindows::new(std::io::BufReader::new(file))?;
    let planned = super::geotiff::planned_size(
        windows.width,
        windows.height,
        &super::ImportOptions::default(),
    );
    Ok(matches!(planned, Ok(None)).then_some(windows))
}
