//! PNG heightmaps, decoded with the `png` crate.
//!
//! Grid point (x, y) is pixel column x, row y (row 0 = the image's top row). Heights are the raw
//! sample values, not rescaled:
//! - grayscale 8-bit gives 0..=255 (1/2/4-bit images are first expanded to 8 bits by the png
//!   crate), 16-bit gives 0..=65535;
//! - gray + alpha: the gray sample (alpha is ignored);
//! - RGB, RGBA and palette images are read as luminance 0.2126·R + 0.7152·G + 0.0722·B
//!   (Rec. 709), which the source note says — unless terrain-RGB is asked for:
//! - terrain-RGB (Mapbox): h = −10000 + (R·65536 + G·256 + B)·0.1 metres, for 8-bit RGB(A).

use super::error::ImportError;
use crate::heightfield::Heightfield;
use png::{BitDepth, ColorType, Transformations};

const FORMAT: &str = "PNG";

fn decoding(e: png::DecodingError) -> ImportError {
    match e {
        png::DecodingError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            ImportError::Truncated {
                format: FORMAT,
                message: "the image data ends early".into(),
            }
        }
        png::DecodingError::LimitsExceeded => ImportError::Unsupported {
            format: FORMAT,
            message: "decoding it needs more than the PNG decoder's 64 MB memory limit (a huge image or metadata chunk)".into(),
        },
        other => ImportError::Malformed {
            format: FORMAT,
            message: other.to_string(),
        },
    }
}

/// The size the IHDR chunk claims, when the file starts with the signature and an IHDR chunk
/// (as the format requires), read before the decoder sees it: the decoder refuses a huge image
/// with a bare "limits are exceeded", where the grid limits name the size and the limit.
fn claimed_size(bytes: &[u8]) -> Option<(usize, usize)> {
    if bytes.get(12..16)? != b"IHDR" {
        return None;
    }
    let be = |at: usize| -> Option<usize> {
        let b: [u8; 4] = bytes.get(at..at + 4)?.try_into().ok()?;
        Some(u32::from_be_bytes(b) as usize)
    };
    Some((be(16)?, be(20)?))
}

/// Mapbox terrain-RGB decoding of one pixel, in metres.
pub(super) fn terrain_rgb_height(r: u8, g: u8, b: u8) -> f64 {
    -10000.0 + f64::from((u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b)) * 0.1
}

/// Decodes a PNG heightmap (see the module doc for how pixels become heights); `name` goes into
/// the source note. The image size is checked against the grid limits before its pixels are
/// decoded. Never panics: every bad input is an [`ImportError`].
pub(super) fn parse(
    bytes: &[u8],
    name: &str,
    terrain_rgb: bool,
) -> Result<Heightfield, ImportError> {
    if let Some((width, height)) = claimed_size(bytes) {
        crate::heightfield::check_size(width, height)?;
    }
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(decoding)?;
    let (width, height) = {
        let info = reader.info();
        (info.width as usize, info.height as usize)
    };
    crate::heightfield::check_size(width, height)?;
    let (color, depth) = reader.output_color_type();
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| ImportError::Malformed {
            format: FORMAT,
            message: "the image is too large to decode".into(),
        })?;
    let mut buf = vec![0u8; size];
    let frame = reader.next_frame(&mut buf).map_err(decoding)?;
    let channels = color.samples();
    let wide = depth == BitDepth::Sixteen;
    let sample_bytes = if wide { 2 } else { 1 };
    let stride = frame.line_size;
    let sample = |x: usize, y: usize, c: usize| -> f64 {
        let o = y * stride + (x * channels + c) * sample_bytes;
        if wide {
            f64::from(u16::from_be_bytes([buf[o], buf[o + 1]]))
        } else {
            f64::from(buf[o])
        }
    };
    let colour = matches!(color, ColorType::Rgb | ColorType::Rgba);
    if terrain_rgb && (!colour || wide) {
        return Err(ImportError::BadOption {
            message: format!(
                "{name}: terrain-RGB needs an 8-bit RGB or RGBA PNG; this one is {color:?} with {} bits per sample",
                depth as u8
            ),
        });
    }
    let mut z = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            z.push(if terrain_rgb {
                let o = y * stride + x * channels;
                terrain_rgb_height(buf[o], buf[o + 1], buf[o + 2])
            } else if colour {
                0.2126 * sample(x, y, 0) + 0.7152 * sample(x, y, 1) + 0.0722 * sample(x, y, 2)
            } else {
                sample(x, y, 0)
            });
        }
    }
    let kind = if terrain_rgb {
        "terrain-RGB (Mapbox) PNG".to_string()
    } else if colour {
        format!(
            "{}-bit colour PNG read as luminance (Rec. 709; use the terrain-RGB option for Mapbox elevation)",
            depth as u8
        )
    } else {
        format!("{}-bit grayscale PNG", depth as u8)
    };
    Ok(Heightfield::new(width, height, z)?
        .with_source(format!("{kind} {name}; image row 0 is grid row 0")))
}
