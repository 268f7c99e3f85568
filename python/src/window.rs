//! A window of a grid file, read on a Dask worker without the rest of the file when it can be:
//! a GeoTIFF's strips or tiles that meet the window are decoded and nothing else. The values
//! are the whole-file importer's, bit for bit; when a window could differ (a nodata cell, whose
//! fill depends on cells outside the window, a grid the importer resamples, another format),
//! the file is read whole once per process and the window cut from it.

use paretomesh::heightfield::{Heightfield, MIN_SIDE, check_size};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use tiff::decoder::{ChunkType, Decoder, DecodingResult};
use tiff::tags::Tag;

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

/// The grid's (width, height) as the importer makes it, read from the header when the file is
/// a GeoTIFF that is read at its own size.
pub fn grid_size(path: &Path) -> Result<(usize, usize), String> {
    if let Some(header) = Header::open(path) {
        return Ok((header.width, header.height));
    }
    let hf = whole(path)?;
    Ok((hf.width(), hf.height()))
}

/// Rows `y0 .. y0 + h`, columns `x0 .. x0 + w` of the grid of `path` (grid row 0 first, as the
/// importer orders them), row-major.
pub fn read(path: &Path, x0: usize, y0: usize, w: usize, h: usize) -> Result<Vec<f64>, String> {
    if let Some(mut header) = Header::open(path)
        && let Some(z) = header.window(x0, y0, w, h)
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

/// An open single-band GeoTIFF that the importer reads at its own size, with what decides how
/// its cells become grid values.
struct Header {
    decoder: Decoder<BufReader<File>>,
    width: usize,
    height: usize,
    /// Grid row 0 is the file's last row (georeferenced files).
    flipped: bool,
    nodata: Option<f64>,
}

impl Header {
    /// `None` for anything but a plain GeoTIFF read as is: the caller reads the file whole.
    fn open(path: &Path) -> Option<Header> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        if ext != "tif" && ext != "tiff" {
            return None;
        }
        let mut decoder = Decoder::new(BufReader::new(File::open(path).ok()?)).ok()?;
        let (w, h) = decoder.dimensions().ok()?;
        let (width, height) = (w as usize, h as usize);
        if width < MIN_SIDE || height < MIN_SIDE || check_size(width, height).is_err() {
            return None;
        }
        let bands: u16 = decoder
            .find_tag_unsigned(Tag::SamplesPerPixel)
            .ok()?
            .unwrap_or(1);
        if bands != 1 {
            return None;
        }
        let numbers = |d: &mut Decoder<BufReader<File>>, tag| match d.find_tag(tag).ok()? {
            Some(v) => v.into_f64_vec().ok(),
            None => None,
        };
        let scale = numbers(&mut decoder, Tag::ModelPixelScaleTag);
        let tie = numbers(&mut decoder, Tag::ModelTiepointTag);
        let flipped = match (scale, tie) {
            (Some(s), Some(t)) if s.len() >= 3 && t.len() >= 6 => {
                let usable = s[0].is_finite() && s[1].is_finite() && s[0] > 0.0 && s[1] > 0.0;
                // The importer also needs finite map coordinates; leave edge cases to it.
                if usable && !t.iter().all(|v| v.is_finite()) {
                    return None;
                }
                usable
            }
            (Some(s), _) if s.len() < 3 => return None,
            (_, Some(t)) if t.len() < 6 => return None,
            _ => false,
        };
        let nodata = match decoder.find_tag(Tag::GdalNodata).ok()? {
            Some(v) => {
                let text = v.into_string().ok()?;
                let text = text.trim_matches(char::from(0)).trim();
                Some(if text.eq_ignore_ascii_case("nan") {
                    f64::NAN
                } else {
                    text.parse::<f64>().ok()?
                })
            }
            None => None,
        };
        Some(Header {
            decoder,
            width,
            height,
            flipped,
            nodata,
        })
    }

    /// The window, or `None` when a cell in it is missing (its fill needs the whole grid) or a
    /// chunk cannot be decoded here.
    fn window(&mut self, x0: usize, y0: usize, w: usize, h: usize) -> Option<Vec<f64>> {
        if x0 + w > self.width || y0 + h > self.height {
            return None;
        }
        // The file rows that hold grid rows y0 .. y0 + h.
        let file_row = |y: usize| if self.flipped { self.height - 1 - y } else { y };
        let (r0, r1) = {
            let (a, b) = (file_row(y0), file_row(y0 + h - 1));
            (a.min(b), a.max(b))
        };
        let (cw, ch) = self.decoder.chunk_dimensions();
        let (cw, ch) = (cw as usize, ch as usize);
        let across = match self.decoder.get_chunk_type() {
            ChunkType::Strip => 1,
            ChunkType::Tile => self.width.div_ceil(cw),
        };
        let mut z = vec![f64::NAN; w * h];
        for cy in r0 / ch..=r1 / ch {
            for cx in x0 / cw..=(x0 + w - 1) / cw {
                let index = (cy * across + cx) as u32;
                let (dw, dh) = self.decoder.chunk_data_dimensions(index);
                let values = samples(self.decoder.read_chunk(index).ok()?)?;
                let stride = if values.len() == (dw as usize) * (dh as usize) {
                    dw as usize
                } else if values.len() == cw * ch {
                    cw
                } else {
                    return None;
                };
                for local_row in 0..dh as usize {
                    let row = cy * ch + local_row;
                    if row < r0 || row > r1 {
                        continue;
                    }
                    let y = if self.flipped {
                        self.height - 1 - row
                    } else {
                        row
                    } - y0;
                    for local_col in 0..dw as usize {
                        let col = cx * cw + local_col;
                        if col < x0 || col >= x0 + w {
                            continue;
                        }
                        let v = values[local_row * stride + local_col];
                        if !v.is_finite() || self.nodata.is_some_and(|n| v == n) {
                            return None;
                        }
                        z[y * w + (col - x0)] = v;
                    }
                }
            }
        }
        z.iter().all(|v| v.is_finite()).then_some(z)
    }
}

/// Decoded samples as f64, as the importer converts them; `None` for 16-bit floats.
fn samples(result: DecodingResult) -> Option<Vec<f64>> {
    Some(match result {
        DecodingResult::U8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U64(v) => v.into_iter().map(|x| x as f64).collect(),
        DecodingResult::I8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I64(v) => v.into_iter().map(|x| x as f64).collect(),
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        DecodingResult::F16(_) => return None,
    })
}
