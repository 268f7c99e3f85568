//! Windows of a grid file for Dask tasks. A GeoTIFF's or a raw grid's are read by the core's
//! window source ([`paretomesh::import::GridWindows`], the one the CLI's tiled runs use),
//! decoding only the strips or tiles a window meets and filling missing cells as the importer
//! does. When the file is not read by windows (a grid the importer resamples; another format)
//! or a window fails, the file is read whole once per process and the window cut from it, so
//! that an error is the importer's own.

use paretomesh::heightfield::Heightfield;
use paretomesh::import::{GridWindows, ImportOptions};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The last grid read whole in this process, by path: a worker asked for many windows of one
/// file reads it once.
static WHOLE: Mutex<Option<(PathBuf, Arc<Heightfield>)>> = Mutex::new(None);

fn whole(path: &Path) -> Result<Arc<Heightfield>, String> {
    let mut cached = WHOLE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((p, hf)) = cached.as_ref()
        && p == path
    {
        return Ok(hf.clone());
    }
    let hf = Arc::new(paretomesh::import::load(path).map_err(|e| e.to_string())?);
    *cached = Some((path.to_path_buf(), hf.clone()));
    Ok(hf)
}

/// The grid's (width, height) as the importer makes it, from the header when the file is a
/// GeoTIFF read at its own size.
pub fn grid_size(path: &Path) -> Result<(usize, usize), String> {
    if let Ok(Some(windows)) = GridWindows::open(path, &ImportOptions::default()) {
        return Ok((windows.width(), windows.height()));
    }
    let hf = whole(path)?;
    Ok((hf.width(), hf.height()))
}

/// Rows `y0 .. y0 + h`, columns `x0 .. x0 + w` of the grid of `path` (grid row 0 first, as the
/// importer orders them), row-major.
pub fn read(path: &Path, x0: usize, y0: usize, w: usize, h: usize) -> Result<Vec<f64>, String> {
    if let Ok(Some(windows)) = GridWindows::open(path, &ImportOptions::default())
        && let Ok(z) = windows.read(x0, y0, w, h)
    {
        return Ok(z);
    }
    let hf = whole(path)?;
    if x0 + w > hf.width() || y0 + h > hf.height() {
        return Err(format!(
            "the window {w}×{h} at ({x0}, {y0}) is outside the {}×{} grid of {}",
            hf.width(),
            hf.height(),
            path.display()
        ));
    }
    let mut z = Vec::with_capacity(w * h);
    for y in y0..y0 + h {
        z.extend_from_slice(&hf.z()[y * hf.width() + x0..][..w]);
    }
    Ok(z)
}
