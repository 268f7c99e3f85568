//! GeoTIFF elevation rasters (DEMs), decoded with the `tiff` crate.
//!
//! Accepted: classic TIFF or BigTIFF, one band of 8/16/32/64-bit integers or 32/64-bit floats,
//! in strips or tiles, uncompressed or compressed with LZW, Deflate or PackBits. Everything else
//! (other codecs, several bands, other sample sizes, 16-bit floats) is refused with a message
//! that names what the file uses.
//!
//! - **Memory.** The grid is allocated once and each strip or tile is decoded straight into
//!   it, so a file read from disk is never held whole beside it: 8 bytes a grid point and one
//!   chunk. Its size is checked from the header, before anything is decoded, against the
//!   grid limits and [`ImportOptions::memory_budget`]; every strip and tile is checked to lie
//!   inside the file, so a truncated file is refused before the long work too.
//!
//! - **Orientation.** Without georeferencing, grid row y is the file's row y (like a PNG). With
//!   ModelPixelScale and ModelTiepoint, the rows are turned over so that grid row 0 is the file's
//!   last (southern) row: then grid x and y grow with the map's x and y, the grid origin and
//!   spacing are map coordinates of sample centres, and an export lands where the DEM lies.
//! - **Nodata.** Cells equal to GDAL_NODATA (tag 42113), and NaN or infinite float cells, are
//!   missing: each takes the value of its nearest valid cell (4-neighbour steps) and is counted.
//! - **Size.** The grid is the file's own size unless another is asked for
//!   ([`ImportOptions::grid_size`]), or the file is over a cap the caller set
//!   ([`ImportOptions::max_points`], a browser tab's); then it is resampled by area averaging
//!   ([`super::resample::area_average`]) and the source note says so. A file over the library's
//!   own limits with neither is refused, never resampled unasked.

use super::error::ImportError;
use super::options::ImportOptions;
use super::resample::{area_average, fill_nearest};
use crate::heightfield::{Georeference, Heightfield};
use crate::heightfield::{MAX_POINTS, MAX_SIDE, MIN_SIDE, check_size};
use std::io::{Cursor, Read, Seek, SeekFrom};
use tiff::TiffError;
use tiff::decoder::{ChunkType, Decoder, DecodingResult, Limits};
use tiff::tags::{CompressionMethod, Tag};

const FORMAT: &str = "GeoTIFF";

/// Most bytes one strip or tile may decode to (256 MiB): the grid is filled one chunk at a
/// time, so only one chunk's samples are held beside it.
pub(super) const MAX_CHUNK_BYTES: usize = 256 << 20;

/// GeoKey 1025, GTRasterTypeGeoKey; value 2 is RasterPixelIsPoint.
const RASTER_TYPE_KEY: u16 = 1025;
/// GeoKey 2048, GeographicTypeGeoKey: the EPSG code of a geographic (longitude, latitude) map.
const GEOGRAPHIC_TYPE_KEY: u16 = 2048;
/// GeoKey 3072, ProjectedCSTypeGeoKey: the EPSG code of a projected map (e.g. 32633, UTM 33N).
const PROJECTED_TYPE_KEY: u16 = 3072;
/// The GeoKey value of a user-defined system, which has no EPSG code.
const USER_DEFINED: u16 = 32767;

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
fn f64_tag<R: Read + Seek>(
    decoder: &mut Decoder<R>,
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

/// Reads the georeferencing tags. Only the values the grid uses are checked.
pub(super) fn georeference<R: Read + Seek>(
    decoder: &mut Decoder<R>,
) -> Result<Georeference, ImportError> {
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
    let inline_key = |key: u16| {
        keys.get(4..)
            .unwrap_or_default()
            .chunks_exact(4)
            .find(|k| k[0] == key && k[1] == 0)
            .map(|k| k[3])
    };
    let pixel_is_point = inline_key(RASTER_TYPE_KEY) == Some(2);
    let epsg = inline_key(PROJECTED_TYPE_KEY)
        .or_else(|| inline_key(GEOGRAPHIC_TYPE_KEY))
        .filter(|&code| code != 0 && code != USER_DEFINED);
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
        epsg,
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
pub(super) fn map_geometry(geo: &Georeference, height: usize) -> Option<([f64; 2], [f64; 2])> {
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

/// Decodes a single-band GeoTIFF held in memory into a height field (see the module doc);
/// `name` goes into the source note. Never panics: every bad input is an [`ImportError`].
pub(super) fn parse(
    bytes: &[u8],
    name: &str,
    options: &ImportOptions,
) -> Result<Heightfield, ImportError> {
    read(Cursor::new(bytes), name, options)
}

/// [`parse`] from any seekable reader, e.g. a file: the samples are decoded one strip or tile
/// at a time straight into the grid, so the file is never held whole beside it.
pub(super) fn read<R: Read + Seek>(
    mut reader: R,
    name: &str,
    options: &ImportOptions,
) -> Result<Heightfield, ImportError> {
    let file_len = reader.seek(SeekFrom::End(0)).map_err(io_error)?;
    let mut magic = [0u8; 4];
    reader.seek(SeekFrom::Start(0)).map_err(io_error)?;
    let bigtiff = reader.read_exact(&mut magic).is_ok() && (magic[2] == 43 || magic[3] == 43);
    reader.seek(SeekFrom::Start(0)).map_err(io_error)?;
    let (mut decoder, width, height) = open(reader)?;
    let geo = georeference(&mut decoder)?;
    let target = planned_size(width, height, options)?;
    check_memory(width, height, target, options.memory_budget)?;
    let chunks = chunk_layout(&mut decoder, width, height, file_len)?;
    let nodata = nodata_value(&geo)?;
    let geometry = map_geometry(&geo, height);
    let mut z = allocate(width, height)?;
    let whole = Rect {
        x0: 0,
        y0: 0,
        w: width,
        h: height,
    };
    decode_window(
        &mut decoder,
        &chunks,
        (width, height),
        nodata,
        geometry.is_some(),
        whole,
        &mut z,
    )?;
    if z.iter().all(|v| v.is_nan()) {
        return Err(malformed(
            "every cell is nodata (or not a finite number); there is no height to read",
        ));
    }
    let filled = fill_nearest(&mut z, width, height);
    let (origin, spacing) = geometry.unwrap_or(([0.0, 0.0], [1.0, 1.0]));
    let mut note = source_note(
        name,
        width,
        height,
        filled,
        &geo,
        geometry.is_some(),
        bigtiff,
    );
    let raster = Raster {
        z,
        width,
        height,
        origin,
        spacing,
    };
    let hf = sized(raster, target, options.grid_size.is_some(), &mut note)?;
    Ok(hf
        .with_filled(filled)
        .with_georeference(geo)
        .with_source(note))
}

/// The size the grid is made at: `None` for the file's own size, else the asked-for size or,
/// under a cap ([`ImportOptions::max_points`]) the file exceeds, the largest size under it with
/// the file's aspect ratio. A file over the library's limits with neither is refused: it is
/// never resampled unasked.
pub(super) fn planned_size(
    width: usize,
    height: usize,
    options: &ImportOptions,
) -> Result<Option<(usize, usize)>, ImportError> {
    let cap = options.max_points.map_or(MAX_POINTS, |c| c.min(MAX_POINTS));
    if let Some((tw, th)) = options.grid_size {
        check_size(tw, th)?;
        if tw.saturating_mul(th) > cap {
            return Err(ImportError::OverLimit {
                format: FORMAT,
                what: "grid points asked for",
                claimed: (tw * th) as u64,
                limit: cap as u64,
            });
        }
        return Ok(((tw, th) != (width, height)).then_some((tw, th)));
    }
    if check_size(width, height).is_ok() && width * height <= cap {
        return Ok(None);
    }
    if options.max_points.is_none() {
        check_size(width, height)?;
    }
    // Fit under the cap and the side limit, keeping the aspect ratio.
    let scale = (cap as f64 / (width as f64 * height as f64))
        .sqrt()
        .min(MAX_SIDE as f64 / width.max(height) as f64)
        .min(1.0);
    let side = |s: usize| ((s as f64 * scale).floor() as usize).max(MIN_SIDE);
    Ok(Some((side(width), side(height))))
}

/// Refuses a grid whose heights (8 bytes a point, and the resampled copy when there is one)
/// need more than `budget` bytes.
fn check_memory(
    width: usize,
    height: usize,
    target: Option<(usize, usize)>,
    budget: Option<u64>,
) -> Result<(), ImportError> {
    let points = (width * height) as u64;
    let resampled = target.map_or(0, |(tw, th)| (tw * th + height * tw) as u64);
    let needed = 8 * (points + resampled);
    match budget {
        Some(available) if needed > available => Err(ImportError::OutOfMemory {
            format: FORMAT,
            width,
            height,
            needed,
            available: Some(available),
        }),
        _ => Ok(()),
    }
}

/// The grid's heights, all NaN until decoded; an allocation the system refuses is an error,
/// not an abort.
fn allocate(width: usize, height: usize) -> Result<Vec<f64>, ImportError> {
    let n = width * height;
    let mut z = Vec::new();
    z.try_reserve_exact(n)
        .map_err(|_| ImportError::OutOfMemory {
            format: FORMAT,
            width,
            height,
            needed: 8 * n as u64,
            available: None,
        })?;
    z.resize(n, f64::NAN);
    Ok(z)
}

/// Where each strip or tile lands in the image.
pub(super) struct Chunks {
    /// Nominal chunk width and height (strips: the image width and rows per strip).
    size: (usize, usize),
    /// Chunks per row of chunks (1 for strips).
    across: usize,
}

impl Chunks {
    /// Rows per strip or tile.
    pub(super) fn rows(&self) -> usize {
        self.size.1
    }
}

/// The strips or tiles of the image, checked against the file's length so that a truncated
/// file is refused before anything is decoded.
pub(super) fn chunk_layout<R: Read + Seek>(
    decoder: &mut Decoder<R>,
    width: usize,
    height: usize,
    file_len: u64,
) -> Result<Chunks, ImportError> {
    let (kind, offsets_tag, counts_tag) = match decoder.get_chunk_type() {
        ChunkType::Strip => ("strip", Tag::StripOffsets, Tag::StripByteCounts),
        ChunkType::Tile => ("tile", Tag::TileOffsets, Tag::TileByteCounts),
    };
    let count = match decoder.get_chunk_type() {
        ChunkType::Strip => decoder.strip_count(),
        ChunkType::Tile => decoder.tile_count(),
    }
    .map_err(decoding)?;
    let (cw, ch) = decoder.chunk_dimensions();
    let (cw, ch) = (cw as usize, ch as usize);
    if cw == 0 || ch == 0 {
        return Err(malformed(format!("its {kind}s are {cw}×{ch} samples")));
    }
    let across = width.div_ceil(cw);
    let expected = across * height.div_ceil(ch);
    let offsets: Vec<u64> = decoder
        .find_tag_unsigned_vec(offsets_tag)
        .map_err(decoding)?
        .unwrap_or_default();
    let counts: Vec<u64> = decoder
        .find_tag_unsigned_vec(counts_tag)
        .map_err(decoding)?
        .unwrap_or_default();
    if count as usize != expected || offsets.len() < expected || counts.len() < expected {
        return Err(unsupported(format!(
            "its layout has {} {kind} offsets and {} byte counts for {expected} {kind}s of {cw}×{ch} samples (planar configuration with several planes, or a damaged directory)",
            offsets.len(),
            counts.len()
        )));
    }
    for (i, (&offset, &bytes)) in offsets.iter().zip(&counts).take(expected).enumerate() {
        if offset.checked_add(bytes).is_none_or(|end| end > file_len) {
            return Err(ImportError::Truncated {
                format: FORMAT,
                message: format!(
                    "{kind} {i} of {expected} lies at bytes {offset}..{} but the file has {file_len} bytes",
                    offset.saturating_add(bytes)
                ),
            });
        }
    }
    Ok(Chunks {
        size: (cw, ch),
        across,
    })
}

/// A rectangle of the grid: columns `x0 .. x0 + w`, grid rows `y0 .. y0 + h`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Rect {
    pub x0: usize,
    pub y0: usize,
    pub w: usize,
    pub h: usize,
}

/// Decodes the chunks that meet `rect` into `out` (row-major, `rect.w` wide, grid row
/// `rect.y0` first) and nothing else: nodata and non-finite samples become NaN, and with
/// `flip` file row r is grid row H−1−r. The whole image is the window that covers it, so a
/// window's values are the whole-image reader's, bit for bit.
#[allow(clippy::too_many_arguments)]
pub(super) fn decode_window<R: Read + Seek>(
    decoder: &mut Decoder<R>,
    chunks: &Chunks,
    (width, height): (usize, usize),
    nodata: Option<f64>,
    flip: bool,
    rect: Rect,
    out: &mut [f64],
) -> Result<(), ImportError> {
    let (cw, ch) = chunks.size;
    let Rect { x0, y0, w, h } = rect;
    // The file rows that hold grid rows y0 .. y0 + h.
    let (f0, f1) = if flip {
        (height - y0 - h, height - y0)
    } else {
        (y0, y0 + h)
    };
    for cy in f0 / ch..=(f1 - 1) / ch {
        for cx in x0 / cw..=(x0 + w - 1) / cw {
            let i = cy * chunks.across + cx;
            let values = samples(decoder.read_chunk(i as u32).map_err(decoding)?)?;
            let (cx0, cy0) = (cx * cw, cy * ch);
            let dw = cw.min(width.saturating_sub(cx0));
            let dh = ch.min(height.saturating_sub(cy0));
            if dw == 0 || dh == 0 || values.len() < dw * dh {
                return Err(malformed(format!(
                    "chunk {i} decoded to {} samples, expected {dw}×{dh}",
                    values.len()
                )));
            }
            let (c0, c1) = (x0.max(cx0), (x0 + w).min(cx0 + dw));
            for file_row in f0.max(cy0)..f1.min(cy0 + dh) {
                let grid_row = if flip {
                    height - 1 - file_row
                } else {
                    file_row
                };
                let row = &values[(file_row - cy0) * dw..][..dw];
                let target = &mut out[(grid_row - y0) * w..][..w];
                for (o, &v) in target[c0 - x0..c1 - x0]
                    .iter_mut()
                    .zip(&row[c0 - cx0..c1 - cx0])
                {
                    *o = if !v.is_finite() || nodata.is_some_and(|n| v == n) {
                        f64::NAN
                    } else {
                        v
                    };
                }
            }
        }
    }
    Ok(())
}

/// The nodata value (GDAL_NODATA) as a number: NaN for "nan", an error when it is not a number.
pub(super) fn nodata_value(geo: &Georeference) -> Result<Option<f64>, ImportError> {
    Ok(match &geo.nodata {
        Some(text) if text.eq_ignore_ascii_case("nan") => Some(f64::NAN),
        Some(text) => Some(text.parse::<f64>().map_err(|_| {
            malformed(format!(
                "GDAL_NODATA (tag 42113) is {text:?}, which is not a number"
            ))
        })?),
        None => None,
    })
}

fn io_error(e: std::io::Error) -> ImportError {
    ImportError::Io {
        path: "GeoTIFF".into(),
        message: e.to_string(),
    }
}

/// Opens the TIFF and checks what this reader supports (one band, compression) before
/// anything is decoded; returns the decoder and the image's width and height.
pub(super) fn open<R: Read + Seek>(reader: R) -> Result<(Decoder<R>, usize, usize), ImportError> {
    let mut limits = Limits::default();
    // One strip or tile is decoded at a time; the grid's own size is checked separately.
    limits.decoding_buffer_size = MAX_CHUNK_BYTES;
    limits.intermediate_buffer_size = MAX_CHUNK_BYTES;
    let mut decoder = Decoder::new(reader).map_err(decoding)?.with_limits(limits);
    let (w, h) = decoder.dimensions().map_err(decoding)?;
    let (width, height) = (w as usize, h as usize);
    if width < MIN_SIDE || height < MIN_SIDE {
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
    let bits: u16 = decoder
        .find_tag_unsigned(Tag::BitsPerSample)
        .map_err(decoding)?
        .unwrap_or(1);
    if !matches!(bits, 8 | 16 | 32 | 64) {
        return Err(unsupported(format!(
            "its samples are {bits} bits wide; ParetoMesh reads 8, 16, 32 and 64-bit samples"
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

/// The source note: the file, its filled cells and how its rows map to the grid.
pub(super) fn source_note(
    name: &str,
    width: usize,
    height: usize,
    filled: usize,
    geo: &Georeference,
    georeferenced: bool,
    bigtiff: bool,
) -> String {
    let kind = if bigtiff {
        "GeoTIFF (BigTIFF)"
    } else {
        "GeoTIFF"
    };
    let mut note = format!("{kind} {name} ({width}×{height}");
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

/// The height field of `raster` at its own size, or resampled to `target`; a resampling is
/// told in `note` with why (`asked`: the caller chose the size, else a cap made it).
fn sized(
    raster: Raster,
    target: Option<(usize, usize)>,
    asked: bool,
    note: &mut String,
) -> Result<Heightfield, ImportError> {
    let Raster {
        z,
        width,
        height,
        origin,
        spacing,
    } = raster;
    Ok(match target {
        Some((tw, th)) => {
            check_size(tw, th)?;
            let averaged = area_average(&z, width, height, tw, th);
            drop(z);
            let spacing = [
                spacing[0] * (width - 1) as f64 / (tw - 1) as f64,
                spacing[1] * (height - 1) as f64 / (th - 1) as f64,
            ];
            let why = if asked {
                "as asked"
            } else {
                "to fit the point cap; choose another size with the grid-size option"
            };
            note.push_str(&format!(
                "; resampled by area averaging onto a {tw}×{th} grid {why}"
            ));
            Heightfield::new(tw, th, averaged)?
                .with_geometry(origin, spacing)?
                .with_resampled()
        }
        None => Heightfield::new(width, height, z)?.with_geometry(origin, spacing)?,
    })
}
