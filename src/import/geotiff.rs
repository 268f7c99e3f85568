//! GeoTIFF elevation rasters (DEMs), decoded with the `tiff` crate.
//!
//! Accepted: one band of 8/16/32/64-bit integers or 32/64-bit floats, in strips or tiles,
//! uncompressed or compressed with LZW, Deflate or PackBits. Everything else (other codecs,
//! several bands, 16-bit floats) is refused with a message that names what the file uses.
//!
//! - **Orientation.** Without georeferencing, grid row y is the file's row y (like a PNG). With
//!   ModelPixelScale and ModelTiepoint, the rows are turned over so that grid row 0 is the file's
//!   last (southern) row: then grid x and y grow with the map's x and y, the grid origin and
//!   spacing are map coordinates of sample centres, and an export lands where the DEM lies.
//! - **Nodata.** Cells equal to GDAL_NODATA (tag 42113), and NaN or infinite float cells, are
//!   missing: each takes the value of its nearest valid cell (4-neighbour steps) and is counted.
//! - **Size.** A grid over the height-field limits, or any grid when another size is asked for,
//!   is resampled by area averaging ([`super::resample::area_average`]); without a size asked
//!   for, an oversized grid is brought to at most [`DEFAULT_MAX_SIDE`] per side.

use super::error::ImportError;
use super::resample::{area_average, fill_nearest};
use super::triangle_mesh::DEFAULT_MAX_SIDE;
use crate::heightfield::{Georeference, Heightfield};
use std::io::Cursor;
use tiff::TiffError;
use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::{CompressionMethod, Tag};

const FORMAT: &str = "GeoTIFF";

/// Most samples a GeoTIFF may hold (2²⁵ ≈ 33.5 M, e.g. 5792²): it is decoded whole before it is
/// resampled, and this keeps that under about 400 MB.
pub const MAX_SOURCE_POINTS: u64 = 1 << 25;

/// GeoKey 1025, GTRasterTypeGeoKey; value 2 is RasterPixelIsPoint.
const RASTER_TYPE_KEY: u16 = 1025;

fn malformed(message: impl Into<String>) -> ImportError {
    ImportError::Malformed {
        format: FORMAT,
        message: message.into(),
    }
}

fn unsupported(message: impl Into<String>) -> ImportError {
    ImportError::Unsupported {
        format: FORMAT,
        message: message.into(),
    }
}

/// The crate's error as an import error: an early end is a truncation, the rest is malformed
/// or unsupported as the decoder says.
fn decoding(e: TiffError) -> ImportError {
    match e {
        TiffError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            ImportError::Truncated {
                format: FORMAT,
                message: "the file ends before the data its directory points to".into(),
            }
        }
        TiffError::UnsupportedError(u) => unsupported(u.to_string()),
        TiffError::LimitsExceeded => unsupported("the image is too large to decode"),
        other => malformed(other.to_string()),
    }
}

fn compression_name(code: u16) -> String {
    match CompressionMethod::from_u16(code) {
        Some(CompressionMethod::Huffman) => "CCITT Huffman (2)".into(),
        Some(CompressionMethod::Fax3) => "CCITT Group 3 fax (3)".into(),
        Some(CompressionMethod::Fax4) => "CCITT Group 4 fax (4)".into(),
        Some(CompressionMethod::JPEG) => "old-style JPEG (6)".into(),
        Some(CompressionMethod::ModernJPEG) => "JPEG (7)".into(),
        Some(CompressionMethod::ZSTD) => "Zstandard (50000)".into(),
        Some(CompressionMethod::WebP) => "WebP (50001)".into(),
        _ if code == 34887 => "LERC (34887)".into(),
        _ if code == 34925 => "LZMA (34925)".into(),
        _ => format!("compression code {code}"),
    }
}

/// Values of a numeric tag as f64, `None` when the tag is absent.
fn f64_tag(
    decoder: &mut Decoder<Cursor<&[u8]>>,
    tag: Tag,
) -> Result<Option<Vec<f64>>, ImportError> {
    match decoder.find_tag(tag).map_err(decoding)? {
        None => Ok(None),
        Some(value) => value
            .into_f64_vec()
            .map(Some)
            .map_err(|_| malformed(format!("tag {} does not hold numbers", tag.to_u16()))),
    }
}

/// The TIFF decoder over the file's bytes.
type TiffDecoder<'a> = Decoder<Cursor<&'a [u8]>>;

/// Reads the georeferencing tags. Only the values the grid uses are checked.
fn georeference(decoder: &mut TiffDecoder<'_>) -> Result<Georeference, ImportError> {
    let scale = f64_tag(decoder, Tag::ModelPixelScaleTag)?;
    let pixel_scale = match scale {
        None => None,
        Some(v) if v.len() >= 3 => Some([v[0], v[1], v[2]]),
        Some(v) => {
            return Err(malformed(format!(
                "ModelPixelScale (tag 33550) needs 3 values, it has {}",
                v.len()
            )));
        }
    };
    let tie = f64_tag(decoder, Tag::ModelTiepointTag)?;
    let tiepoint = match tie {
        None => None,
        Some(v) if v.len() >= 6 => Some([v[0], v[1], v[2], v[3], v[4], v[5]]),
        Some(v) => {
            return Err(malformed(format!(
                "ModelTiepoint (tag 33922) needs 6 values, it has {}",
                v.len()
            )));
        }
    };
    let keys = match decoder
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(decoding)?
    {
        Some(value) => value.into_u16_vec().unwrap_or_default(),
        None => Vec::new(),
    };
    // Header of 4 shorts, then (key, location, count, value) per key; location 0 = inline value.
    let pixel_is_point = keys
        .get(4..)
        .unwrap_or_default()
        .chunks_exact(4)
        .any(|k| k[0] == RASTER_TYPE_KEY && k[1] == 0 && k[3] == 2);
    let nodata = match decoder.find_tag(Tag::GdalNodata).map_err(decoding)? {
        Some(value) => Some(
            value
                .into_string()
                .map_err(|_| malformed("GDAL_NODATA (tag 42113) is not text"))?
                .trim_matches(char::from(0))
                .trim()
                .to_string(),
        ),
        None => None,
    };
    Ok(Georeference {
        pixel_scale,
        tiepoint,
        pixel_is_point,
        nodata,
    })
}

/// The decoded samples as f64, or an error naming a sample type that is not read.
fn samples(result: DecodingResult) -> Result<Vec<f64>, ImportError> {
    Ok(match result {
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
        DecodingResult::F16(_) => {
            return Err(unsupported(
                "the samples are 16-bit floats; ParetoMesh reads 8/16/32-bit integers and 32/64-bit floats",
            ));
        }
    })
}

/// Grid origin and spacing in map units from the georeferencing, for the rows turned over so
/// that row 0 is the southern one; `None` without both tags or with an unusable scale.
fn map_geometry(geo: &Georeference, height: usize) -> Option<([f64; 2], [f64; 2])> {
    let ([sx, sy, _], [i, j, _, x, y, _]) = (geo.pixel_scale?, geo.tiepoint?);
    if !(sx.is_finite() && sy.is_finite() && sx > 0.0 && sy > 0.0) {
        return None;
    }
    // The map position of sample centre (0, 0): a PixelIsArea tie point is a pixel corner.
    let centre = if geo.pixel_is_point { 0.0 } else { 0.5 };
    let x0 = x + (centre - i) * sx;
    let y0 = y - (centre - j) * sy;
    let south = y0 - (height - 1) as f64 * sy;
    (x0.is_finite() && south.is_finite()).then_some(([x0, south], [sx, sy]))
}

/// Decodes a single-band GeoTIFF into a height field (see the module doc); `grid_size` asks for
/// a resampled size, `name` goes into the source note. Never panics: every bad input is an
/// [`ImportError`].
pub fn parse(
    bytes: &[u8],
    name: &str,
    grid_size: Option<(usize, usize)>,
) -> Result<Heightfield, ImportError> {
    let (mut decoder, width, height) = open(bytes)?;
    let geo = georeference(&mut decoder)?;
    let mut z = samples(decoder.read_image().map_err(decoding)?)?;
    if z.len() != width * height {
        return Err(malformed(format!(
            "a {width}×{height} image decoded to {} samples",
            z.len()
        )));
    }
    // Missing cells become NaN, then take their nearest valid value.
    mark_missing(&mut z, &geo)?;
    let filled = fill_nearest(&mut z, width, height);

    let geometry = map_geometry(&geo, height);
    if geometry.is_some() {
        // Row 0 becomes the southern row, so that grid y grows with map y.
        let flipped: Vec<f64> = z.chunks_exact(width).rev().flatten().copied().collect();
        z = flipped;
    }
    let (origin, spacing) = geometry.unwrap_or(([0.0, 0.0], [1.0, 1.0]));
    let mut note = source_note(name, width, height, filled, &geo, geometry.is_some());
    let raster = Raster {
        z,
        width,
        height,
        origin,
        spacing,
    };
    let hf = sized(raster, grid_size, &mut note)?;
    Ok(hf
        .with_filled(filled)
        .with_georeference(geo)
        .with_source(note))
}

/// Opens the TIFF and checks what this reader supports (size, one band, compression) before
/// anything is decoded; returns the decoder and the image's width and height.
fn open(bytes: &[u8]) -> Result<(TiffDecoder<'_>, usize, usize), ImportError> {
    let mut limits = Limits::default();
    limits.decoding_buffer_size = (MAX_SOURCE_POINTS * 8) as usize;
    let mut decoder = Decoder::new(Cursor::new(bytes))
        .map_err(decoding)?
        .with_limits(limits);
    let (w, h) = decoder.dimensions().map_err(decoding)?;
    let (width, height) = (w as usize, h as usize);
    if u64::from(w) * u64::from(h) > MAX_SOURCE_POINTS {
        return Err(ImportError::OverLimit {
            format: FORMAT,
            what: "samples",
            claimed: u64::from(w) * u64::from(h),
            limit: MAX_SOURCE_POINTS,
        });
    }
    if width < crate::heightfield::MIN_SIDE || height < crate::heightfield::MIN_SIDE {
        return Err(crate::heightfield::HeightfieldError::TooSmall { width, height }.into());
    }
    let bands: u16 = decoder
        .find_tag_unsigned(Tag::SamplesPerPixel)
        .map_err(decoding)?
        .unwrap_or(1);
    if bands != 1 {
        return Err(unsupported(format!(
            "it has {bands} bands (samples per pixel); ParetoMesh reads single-band elevation rasters; extract one band first, e.g. gdal_translate -b 1"
        )));
    }
    let compression: u16 = decoder
        .find_tag_unsigned(Tag::Compression)
        .map_err(decoding)?
        .unwrap_or(1);
    if !matches!(compression, 1 | 5 | 8 | 0x80B2 | 0x8005) {
        return Err(unsupported(format!(
            "it uses {} compression; ParetoMesh reads uncompressed, LZW, Deflate and PackBits GeoTIFFs; convert it first, e.g. gdal_translate -co COMPRESS=DEFLATE",
            compression_name(compression)
        )));
    }
    Ok((decoder, width, height))
}

/// Turns the cells that are nodata (GDAL_NODATA) or not finite into NaN; an error when no
/// cell is left or the nodata value is not a number.
fn mark_missing(z: &mut [f64], geo: &Georeference) -> Result<(), ImportError> {
    let nodata = match &geo.nodata {
        Some(text) if text.eq_ignore_ascii_case("nan") => Some(f64::NAN),
        Some(text) => Some(text.parse::<f64>().map_err(|_| {
            malformed(format!(
                "GDAL_NODATA (tag 42113) is {text:?}, which is not a number"
            ))
        })?),
        None => None,
    };
    for v in z.iter_mut() {
        if !v.is_finite() || nodata.is_some_and(|n| *v == n) {
            *v = f64::NAN;
        }
    }
    if z.iter().all(|v| v.is_nan()) {
        return Err(malformed(
            "every cell is nodata (or not a finite number); there is no height to read",
        ));
    }
    Ok(())
}

/// The source note: the file, its filled cells and how its rows map to the grid.
fn source_note(
    name: &str,
    width: usize,
    height: usize,
    filled: usize,
    geo: &Georeference,
    georeferenced: bool,
) -> String {
    let mut note = format!("GeoTIFF {name} ({width}×{height}");
    if let Some(text) = &geo.nodata {
        note.push_str(&format!(
            "; {filled} nodata cells (GDAL_NODATA {text}) filled from their nearest valid cell"
        ));
    } else if filled > 0 {
        note.push_str(&format!(
            "; {filled} cells that were not finite numbers filled from their nearest valid cell"
        ));
    }
    note.push(')');
    note.push_str(if georeferenced {
        "; grid row 0 is the southern (last) row, grid x and y are map coordinates of sample centres"
    } else {
        "; no georeferencing (ModelPixelScale and ModelTiepoint), image row 0 is grid row 0"
    });
    note
}

/// The decoded heights, grid row 0 first, with their map placement.
struct Raster {
    z: Vec<f64>,
    width: usize,
    height: usize,
    origin: [f64; 2],
    spacing: [f64; 2],
}

/// The height field of `raster` at `grid_size`, or, unasked, at its own size when that fits
/// the limit and else scaled down to [`DEFAULT_MAX_SIDE`]; a resampling is told in `note`.
fn sized(
    raster: Raster,
    grid_size: Option<(usize, usize)>,
    note: &mut String,
) -> Result<Heightfield, ImportError> {
    let Raster {
        z,
        width,
        height,
        origin,
        spacing,
    } = raster;
    let fits = crate::heightfield::check_size(width, height).is_ok();
    let target = match grid_size {
        Some(size) => Some(size),
        None if fits => None,
        None => {
            let scale = DEFAULT_MAX_SIDE as f64 / width.max(height) as f64;
            let side =
                |s: usize| ((s as f64 * scale).round() as usize).max(crate::heightfield::MIN_SIDE);
            Some((side(width), side(height)))
        }
    };
    Ok(match target {
        Some((tw, th)) if (tw, th) != (width, height) => {
            crate::heightfield::check_size(tw, th)?;
            let averaged = area_average(&z, width, height, tw, th);
            let spacing = [
                spacing[0] * (width - 1) as f64 / (tw - 1) as f64,
                spacing[1] * (height - 1) as f64 / (th - 1) as f64,
            ];
            let why = if grid_size.is_some() {
                "as asked"
            } else {
                "because the grid is over the size limit; choose another size with the grid-size option"
            };
            note.push_str(&format!(
                "; resampled by area averaging onto a {tw}×{th} grid {why}"
            ));
            Heightfield::new(tw, th, averaged)?
                .with_geometry(origin, spacing)?
                .with_resampled()
        }
        _ => Heightfield::new(width, height, z)?.with_geometry(origin, spacing)?,
    })
}
