//! GeoTIFF import: the files in tests/data made with GDAL from the raw grids (see SOURCES.md),
//! and files written in memory with the `tiff` crate's encoder for the other sample types.

use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::import::{ImportError, ImportOptions};
use std::io::Cursor;
use std::path::PathBuf;
use tiff::encoder::{TiffEncoder, colortype};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn raw(name: &str) -> Vec<f64> {
    std::fs::read(data(name))
        .unwrap()
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
        .collect()
}

fn load(name: &str) -> Result<Heightfield, ImportError> {
    import::load(&data(name))
}

/// Grid row y of a georeferenced file is file row H−1−y.
fn file_row_order(hf: &Heightfield) -> Vec<f64> {
    hf.z()
        .chunks_exact(hf.width())
        .rev()
        .flatten()
        .copied()
        .collect()
}

#[test]
fn int16_lzw_with_nodata_fills_and_counts_the_missing_cells() {
    let hf = load("volcano_87x61_int16_lzw_nodata.tif").unwrap();
    assert_eq!((hf.width(), hf.height()), (87, 61));
    let source = raw("volcano_87x61.f32");
    let z = file_row_order(&hf);
    // The 14 cells written as -9999: a 4×3 block, the corner (0, 0) and (50, 30).
    let mut missing: Vec<usize> = (5..8)
        .flat_map(|y| (10..14).map(move |x| y * 87 + x))
        .collect();
    missing.extend([0, 30 * 87 + 50]);
    assert_eq!(hf.filled(), 14);
    for (i, (&got, &want)) in z.iter().zip(&source).enumerate() {
        if missing.contains(&i) {
            continue;
        }
        assert_eq!(got, want, "cell {i}");
    }
    // Each missing cell took the value of a valid cell at the nearest 4-neighbour distance.
    for &i in &missing {
        assert_ne!(z[i], -9999.0);
        let (x, y) = (i % 87, i / 87);
        let nearest = (0..source.len())
            .filter(|j| !missing.contains(j))
            .map(|j| (j % 87).abs_diff(x) + (j / 87).abs_diff(y))
            .min()
            .unwrap();
        let candidates: Vec<f64> = (0..source.len())
            .filter(|j| {
                !missing.contains(j) && (j % 87).abs_diff(x) + (j / 87).abs_diff(y) == nearest
            })
            .map(|j| source[j])
            .collect();
        assert!(candidates.contains(&z[i]), "cell {i}: {}", z[i]);
    }
    assert!(hf.source().contains("14 nodata cells"), "{}", hf.source());
    // Spacing 10 m; sample centres: the tie point is the upper-left corner (pixel is area).
    let geo = hf.georeference().expect("georeferencing kept");
    assert_eq!(geo.pixel_scale.unwrap()[..2], [10.0, 10.0]);
    assert_eq!(geo.tiepoint.unwrap()[3..5], [2667400.0, 6478710.0]);
    assert!(!geo.pixel_is_point);
    assert_eq!(geo.nodata.as_deref(), Some("-9999"));
    assert_eq!(hf.spacing(), [10.0, 10.0]);
    assert_eq!(hf.origin(), [2667405.0, 6478710.0 - 5.0 - 600.0]);
    // The grid's own coordinates are map coordinates: the north-west sample sits at the top.
    let north_west = hf.to_world(hf.index(0, 60), 0.0);
    assert_eq!(north_west[..2], [2667405.0, 6478705.0]);
}

#[test]
fn float32_tiled_deflate_equals_the_source_grid() {
    let hf = load("jacksboro_65x65_float32_tiled_deflate.tif").unwrap();
    assert_eq!((hf.width(), hf.height()), (65, 65));
    // f32 in, f32 out: exact.
    assert_eq!(file_row_order(&hf), raw("jacksboro_65x65.f32"));
    assert_eq!(hf.filled(), 0);
    let geo = hf.georeference().unwrap();
    // GDAL writes a PixelIsPoint file's tie point at the centre of pixel (0, 0).
    assert!(geo.pixel_is_point);
    assert_eq!(hf.spacing(), [10.0, 10.0]);
    assert_eq!(hf.origin(), [500005.0, 4000005.0]);
}

#[test]
fn float64_without_georeferencing_keeps_the_file_order() {
    let hf = load("camera_33x33_float64.tif").unwrap();
    assert_eq!(hf.z(), raw("camera_33x33.f32"));
    assert_eq!(hf.origin(), [0.0, 0.0]);
    assert_eq!(hf.spacing(), [1.0, 1.0]);
    let geo = hf.georeference().unwrap();
    assert_eq!((geo.pixel_scale, geo.tiepoint), (None, None));
    assert!(hf.source().contains("no georeferencing"), "{}", hf.source());
}

#[test]
fn uint16_packbits_in_several_strips_equals_the_source_grid() {
    let hf = load("volcano_87x61_uint16_packbits.tif").unwrap();
    assert_eq!(hf.z(), raw("volcano_87x61.f32"));
}

#[test]
fn unsupported_compression_and_bands_are_named() {
    let err = load("bunny_33x33_jpeg.tif").unwrap_err();
    assert!(matches!(err, ImportError::Unsupported { .. }), "{err}");
    let message = err.to_string();
    assert!(message.contains("JPEG"), "{message}");
    assert!(message.contains("LZW, Deflate and PackBits"), "{message}");

    let err = load("camera_33x33_two_bands.tif").unwrap_err();
    assert!(matches!(err, ImportError::Unsupported { .. }), "{err}");
    assert!(err.to_string().contains("2 bands"), "{err}");
}

fn encode<C: colortype::ColorType>(width: u32, height: u32, data: &[C::Inner]) -> Vec<u8>
where
    [C::Inner]: tiff::encoder::TiffValue,
{
    let mut out = Cursor::new(Vec::new());
    TiffEncoder::new(&mut out)
        .unwrap()
        .write_image::<C>(width, height, data)
        .unwrap();
    out.into_inner()
}

fn parse(bytes: &[u8]) -> Result<Heightfield, ImportError> {
    import::from_bytes("dem.tif", bytes, None, &ImportOptions::default())
}

#[test]
fn every_integer_and_float_sample_type_reads_its_values() {
    let (w, h) = (5u32, 4u32);
    let n = (w * h) as usize;
    let expect = |values: Vec<f64>, bytes: Vec<u8>| {
        let hf = parse(&bytes).unwrap();
        assert_eq!(hf.z(), values);
    };
    let u8s: Vec<u8> = (0..n).map(|i| (i * 13) as u8).collect();
    expect(
        u8s.iter().map(|&v| f64::from(v)).collect(),
        encode::<colortype::Gray8>(w, h, &u8s),
    );
    let i8s: Vec<i8> = (0..n).map(|i| i as i8 - 10).collect();
    expect(
        i8s.iter().map(|&v| f64::from(v)).collect(),
        encode::<colortype::GrayI8>(w, h, &i8s),
    );
    let u16s: Vec<u16> = (0..n).map(|i| (i * 3001) as u16).collect();
    expect(
        u16s.iter().map(|&v| f64::from(v)).collect(),
        encode::<colortype::Gray16>(w, h, &u16s),
    );
    let i16s: Vec<i16> = (0..n).map(|i| (i as i16 - 10) * 1000).collect();
    expect(
        i16s.iter().map(|&v| f64::from(v)).collect(),
        encode::<colortype::GrayI16>(w, h, &i16s),
    );
    let u32s: Vec<u32> = (0..n).map(|i| (i as u32) * 200_000_000).collect();
    expect(
        u32s.iter().map(|&v| f64::from(v)).collect(),
        encode::<colortype::Gray32>(w, h, &u32s),
    );
    let i32s: Vec<i32> = (0..n).map(|i| (i as i32 - 10) * 100_000_000).collect();
    expect(
        i32s.iter().map(|&v| f64::from(v)).collect(),
        encode::<colortype::GrayI32>(w, h, &i32s),
    );
    let f32s: Vec<f32> = (0..n).map(|i| i as f32 * 0.1 - 0.7).collect();
    expect(
        f32s.iter().map(|&v| f64::from(v)).collect(),
        encode::<colortype::Gray32Float>(w, h, &f32s),
    );
    let f64s: Vec<f64> = (0..n).map(|i| i as f64 * 0.1 - 1e9).collect();
    expect(f64s.clone(), encode::<colortype::Gray64Float>(w, h, &f64s));
}

#[test]
fn nan_cells_are_missing_even_without_a_nodata_tag() {
    let mut values = vec![1.0f32; 16];
    values[5] = f32::NAN;
    values[6] = f32::INFINITY;
    let hf = parse(&encode::<colortype::Gray32Float>(4, 4, &values)).unwrap();
    assert_eq!(hf.filled(), 2);
    assert!(hf.z().iter().all(|&v| v == 1.0));
    let err = parse(&encode::<colortype::Gray32Float>(2, 2, &[f32::NAN; 4])).unwrap_err();
    assert!(err.to_string().contains("every cell is nodata"), "{err}");
}

#[test]
fn a_grid_size_resamples_by_area_averaging() {
    let options = ImportOptions {
        grid_size: Some((44, 31)),
        ..ImportOptions::default()
    };
    let path = data("volcano_87x61_int16_lzw_nodata.tif");
    let full = import::load(&path).unwrap();
    let small = import::load_with(&path, &options).unwrap();
    assert_eq!((small.width(), small.height()), (44, 31));
    // Same extent: the spacing doubles exactly (86/43, 60/30), the corners stay put.
    assert_eq!(small.spacing(), [20.0, 20.0]);
    assert_eq!(small.origin(), full.origin());
    // Each inner point is the cell mean of the full grid: weights ½, 1, ½ in each direction.
    let (x, y) = (10, 7);
    let mut sum = 0.0;
    for (dy, wy) in [(-1i64, 0.5), (0, 1.0), (1, 0.5)] {
        for (dx, wx) in [(-1i64, 0.5), (0, 1.0), (1, 0.5)] {
            let z = full.z_at((2 * x + dx) as usize, (2 * y + dy) as usize);
            sum += wx * wy * z;
        }
    }
    assert!((small.z_at(x as usize, y as usize) - sum / 4.0).abs() < 1e-9);
    assert!(
        small.source().contains("area averaging"),
        "{}",
        small.source()
    );
    assert_eq!(small.filled(), 14);
}

#[test]
fn a_grid_over_the_limits_is_refused_not_resampled() {
    // One sample over the 16 384-per-side limit, and cheap: 16 385 × 2.
    let (w, h) = (16_385u32, 2u32);
    let values: Vec<u8> = (0..w * h).map(|i| (i % 251) as u8).collect();
    let bytes = encode::<colortype::Gray8>(w, h, &values);
    let err = parse(&bytes).unwrap_err();
    assert!(
        err.to_string().contains("exact integer predicates"),
        "{err}"
    );
    // A size asked for resamples it, and the note says so.
    let options = ImportOptions {
        grid_size: Some((257, 2)),
        ..ImportOptions::default()
    };
    let hf = import::from_bytes("dem.tif", &bytes, None, &options).unwrap();
    assert_eq!((hf.width(), hf.height()), (257, 2));
    assert!(hf.source().contains("as asked"), "{}", hf.source());
    // Asked-for sizes are checked against the grid limits.
    let options = ImportOptions {
        grid_size: Some((1, 5)),
        ..ImportOptions::default()
    };
    let err = import::from_bytes("dem.tif", &bytes, None, &options).unwrap_err();
    assert!(err.to_string().contains("at least 2×2"), "{err}");
}

#[test]
fn a_point_cap_fits_the_grid_under_it_and_says_so() {
    let (w, h) = (300u32, 200u32);
    let values: Vec<u16> = (0..w * h).map(|i| (i % 1000) as u16).collect();
    let bytes = encode::<colortype::Gray16>(w, h, &values);
    // Under the cap: the native size.
    let roomy = ImportOptions {
        max_points: Some(60_000),
        ..ImportOptions::default()
    };
    let hf = import::from_bytes("dem.tif", &bytes, None, &roomy).unwrap();
    assert_eq!((hf.width(), hf.height()), (300, 200));
    assert!(!hf.resampled());
    // Over it: the largest grid under it with the same aspect ratio.
    let tight = ImportOptions {
        max_points: Some(6_000),
        ..ImportOptions::default()
    };
    let hf = import::from_bytes("dem.tif", &bytes, None, &tight).unwrap();
    assert!(hf.len() <= 6_000, "{}×{}", hf.width(), hf.height());
    assert_eq!((hf.width(), hf.height()), (94, 63));
    assert!(hf.resampled());
    assert!(hf.source().contains("point cap"), "{}", hf.source());
}

/// A valid 8-bit image whose ImageWidth and ImageLength (tags 256 and 257) are then raised to
/// `side`: the size checks must come before any decoding.
fn claiming(side: u32) -> Vec<u8> {
    let mut bytes = encode::<colortype::Gray8>(4, 4, &[0u8; 16]);
    let ifd = u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize;
    let count = u16::from_le_bytes([bytes[ifd], bytes[ifd + 1]]) as usize;
    for e in 0..count {
        let at = ifd + 2 + 12 * e;
        let tag = u16::from_le_bytes([bytes[at], bytes[at + 1]]);
        let kind = u16::from_le_bytes([bytes[at + 2], bytes[at + 3]]);
        if tag == 256 || tag == 257 {
            match kind {
                3 => bytes[at + 8..at + 10].copy_from_slice(&(side as u16).to_le_bytes()),
                _ => bytes[at + 8..at + 12].copy_from_slice(&side.to_le_bytes()),
            }
        }
    }
    bytes
}

#[test]
fn a_header_over_the_limits_or_the_memory_is_refused_before_decoding() {
    let err = parse(&claiming(20_000)).unwrap_err();
    assert!(matches!(err, ImportError::Grid(_)), "{err}");
    assert!(err.to_string().contains("16384 per side"), "{err}");
    // 10 000² fits the limits but not a 64 MiB budget: refused from the header.
    let budget = ImportOptions {
        memory_budget: Some(64 << 20),
        ..ImportOptions::default()
    };
    let err = import::from_bytes("dem.tif", &claiming(10_000), None, &budget).unwrap_err();
    assert!(matches!(err, ImportError::OutOfMemory { .. }), "{err}");
    let text = err.to_string();
    assert!(
        text.contains("10000×10000") && text.contains("0.75 GiB") && text.contains("0.06 GiB"),
        "{text}"
    );
}

/// A float32 image written in strips of `rows` rows, as a classic TIFF or a BigTIFF.
fn striped(width: u32, height: u32, rows: u32, big: bool) -> (Vec<f32>, Vec<u8>) {
    let values: Vec<f32> = (0..width * height)
        .map(|i| ((i % width) as f32 * 0.37).sin() * 100.0 + (i / width) as f32)
        .collect();
    let mut out = Cursor::new(Vec::new());
    if big {
        let mut encoder = TiffEncoder::new_big(&mut out).unwrap();
        let mut image = encoder
            .new_image::<colortype::Gray32Float>(width, height)
            .unwrap();
        image.rows_per_strip(rows).unwrap();
        image.write_data(&values).unwrap();
    } else {
        let mut encoder = TiffEncoder::new(&mut out).unwrap();
        let mut image = encoder
            .new_image::<colortype::Gray32Float>(width, height)
            .unwrap();
        image.rows_per_strip(rows).unwrap();
        image.write_data(&values).unwrap();
    }
    (values, out.into_inner())
}

#[test]
fn bigtiff_in_several_strips_reads_its_values() {
    let (values, bytes) = striped(130, 70, 16, true);
    assert_eq!(&bytes[..4], b"II+\0", "the encoder wrote a BigTIFF");
    let hf = parse(&bytes).unwrap();
    assert_eq!((hf.width(), hf.height()), (130, 70));
    let expected: Vec<f64> = values.iter().map(|&v| f64::from(v)).collect();
    assert_eq!(hf.z(), expected);
    assert!(hf.source().contains("BigTIFF"), "{}", hf.source());
    // The same file read from disk, a strip at a time, gives the same grid.
    let path = std::env::temp_dir().join(format!("paretomesh-big-{}.tif", std::process::id()));
    std::fs::write(&path, &bytes).unwrap();
    let from_file = import::load(&path);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(from_file.unwrap().z(), hf.z());
}

#[test]
fn a_bigtiff_with_an_unsupported_layout_is_named() {
    let mut out = Cursor::new(Vec::new());
    TiffEncoder::new_big(&mut out)
        .unwrap()
        .write_image::<colortype::RGB8>(4, 3, &[7u8; 36])
        .unwrap();
    let err = parse(&out.into_inner()).unwrap_err();
    assert!(matches!(err, ImportError::Unsupported { .. }), "{err}");
    assert!(err.to_string().contains("3 bands"), "{err}");
}

#[test]
fn a_truncated_strip_is_refused_before_decoding() {
    for big in [false, true] {
        let (_, bytes) = striped(64, 64, 8, big);
        let hf = parse(&bytes).unwrap();
        assert_eq!(hf.len(), 64 * 64);
        let cut = truncate_last_strip(&bytes, big);
        assert_eq!(cut.len(), bytes.len());
        let err = parse(&cut).unwrap_err();
        assert!(matches!(err, ImportError::Truncated { .. }), "{err}");
        assert!(err.to_string().contains("strip 7 of 8"), "{err}");
    }
}
#[test]
fn truncated_and_garbage_bytes_are_errors_not_panics() {
    let names = [
        "volcano_87x61_int16_lzw_nodata.tif",
        "jacksboro_65x65_float32_tiled_deflate.tif",
        "camera_33x33_float64.tif",
        "volcano_87x61_uint16_packbits.tif",
    ];
    for name in names {
        let bytes = std::fs::read(data(name)).unwrap();
        // (The last bytes of a GDAL file may be padding, so cuts stop at half the file.)
        for cut in [0, 3, 8, 20, 100, bytes.len() / 2] {
            match parse(&bytes[..cut]) {
                Ok(_) => panic!("{name} cut at {cut} was read"),
                Err(e) => assert!(e.to_string().contains("GeoTIFF") || cut < 4, "{e}"),
            }
        }
        // Flipped bytes anywhere: an error or a grid, never a panic.
        let mut state = 0x2545F491u32;
        for _ in 0..300 {
            let mut damaged = bytes.clone();
            for _ in 0..4 {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                let at = state as usize % damaged.len();
                damaged[at] ^= (state >> 24) as u8 | 1;
            }
            let _ = parse(&damaged);
        }
    }
    let err = parse(b"II*\0garbage").map(|_| ()).unwrap_err();
    assert!(err.to_string().contains("GeoTIFF"), "{err}");
}

/// The file with its last strip's byte count (tag 279) raised past the end of the file, as in
/// a file cut short after its directory was written.
fn truncate_last_strip(bytes: &[u8], big: bool) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let u16_at = |b: &[u8], at: usize| u16::from_le_bytes([b[at], b[at + 1]]) as usize;
    let u64_at = |b: &[u8], at: usize, n: usize| {
        let mut v = [0u8; 8];
        v[..n].copy_from_slice(&b[at..at + n]);
        u64::from_le_bytes(v) as usize
    };
    let (ifd, entries, entry_len, word) = if big {
        let ifd = u64_at(bytes, 8, 8);
        (ifd, u64_at(bytes, ifd, 8), 20, 8)
    } else {
        let ifd = u64_at(bytes, 4, 4);
        (ifd, u16_at(bytes, ifd), 12, 4)
    };
    let first = ifd + if big { 8 } else { 2 };
    for e in 0..entries {
        let at = first + entry_len * e;
        if u16_at(bytes, at) != 279 {
            continue;
        }
        let size = match u16_at(bytes, at + 2) {
            3 => 2,
            4 => 4,
            16 => 8,
            other => panic!("byte counts of type {other}"),
        };
        let count = u64_at(bytes, at + 4, word);
        let values = if count * size <= word {
            at + 4 + word
        } else {
            u64_at(bytes, at + 4 + word, word)
        };
        let last = values + (count - 1) * size;
        let raised = (bytes.len() as u64).to_le_bytes();
        out[last..last + size].copy_from_slice(&raised[..size]);
        return out;
    }
    panic!("no StripByteCounts tag");
}

/// A little-endian classic TIFF of float32 `values` (`width × height`) in uncompressed tiles of
/// `tile × tile` samples, padded at the right and bottom edges as TIFF requires: the `tiff`
/// crate's encoder writes strips only.
fn tiled(width: u32, height: u32, tile: u32, values: &[f32]) -> Vec<u8> {
    let (across, down) = (width.div_ceil(tile), height.div_ceil(tile));
    let tile_bytes = tile * tile * 4;
    let mut data = Vec::new();
    for ty in 0..down {
        for tx in 0..across {
            for r in 0..tile {
                for c in 0..tile {
                    let (x, y) = (tx * tile + c, ty * tile + r);
                    let v = if x < width && y < height {
                        values[(y * width + x) as usize]
                    } else {
                        -9999.0
                    };
                    data.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
    let count = across * down;
    let data_at = 8u32;
    let offsets_at = data_at + data.len() as u32;
    let counts_at = offsets_at + 4 * count;
    let ifd_at = counts_at + 4 * count;
    let mut out = b"II*\0".to_vec();
    out.extend_from_slice(&ifd_at.to_le_bytes());
    out.extend_from_slice(&data);
    for k in 0..count {
        out.extend_from_slice(&(data_at + k * tile_bytes).to_le_bytes());
    }
    for _ in 0..count {
        out.extend_from_slice(&tile_bytes.to_le_bytes());
    }
    // (tag, type, count, value): SHORT = 3, LONG = 4; entries in increasing tag order.
    let entries: [(u16, u16, u32, u32); 11] = [
        (256, 4, 1, width),
        (257, 4, 1, height),
        (258, 3, 1, 32),
        (259, 3, 1, 1),
        (262, 3, 1, 1),
        (277, 3, 1, 1),
        (322, 4, 1, tile),
        (323, 4, 1, tile),
        (324, 4, count, offsets_at),
        (325, 4, count, counts_at),
        (339, 3, 1, 3),
    ];
    out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    for (tag, kind, n, value) in entries {
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&n.to_le_bytes());
        out.extend_from_slice(&value.to_le_bytes());
    }
    out.extend_from_slice(&0u32.to_le_bytes());
    out
}

#[test]
fn tiles_land_in_place_including_the_padded_edge_tiles() {
    // 40×24 in 16×16 tiles: 3×2 tiles, the right column and bottom row padded.
    let (w, h) = (40u32, 24u32);
    let values: Vec<f32> = (0..w * h).map(|i| i as f32 * 0.5 - 7.0).collect();
    let hf = parse(&tiled(w, h, 16, &values)).unwrap();
    assert_eq!((hf.width(), hf.height()), (40, 24));
    let expected: Vec<f64> = values.iter().map(|&v| f64::from(v)).collect();
    assert_eq!(hf.z(), expected);
    assert_eq!(hf.filled(), 0);
}

/// `count` random windows of a `width`×`height` image, with the whole image and its corners.
fn random_windows(width: usize, height: usize, count: usize) -> Vec<(usize, usize, usize, usize)> {
    let mut state = 0x9E37_79B9u32;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as usize % n
    };
    let mut out = vec![
        (0, 0, width, height),
        (width - 1, height - 1, 1, 1),
        (0, 0, 1, 1),
    ];
    for _ in 0..count {
        let (x0, y0) = (next(width), next(height));
        out.push((x0, y0, 1 + next(width - x0), 1 + next(height - y0)));
    }
    out
}

/// Every window of `windows` against the whole-image grid `hf`: the same values, and NaN
/// exactly on the cells the whole reader filled.
fn assert_windows_match<R: std::io::Read + std::io::Seek>(
    name: &str,
    windows: &mut import::GeoTiffWindows<R>,
    hf: &Heightfield,
) {
    assert_eq!(
        (windows.width(), windows.height()),
        (hf.width(), hf.height())
    );
    for (x0, y0, w, h) in random_windows(hf.width(), hf.height(), 40) {
        let z = windows.read(x0, y0, w, h).unwrap();
        assert_eq!(z.len(), w * h);
        let mut missing = 0;
        for y in 0..h {
            for x in 0..w {
                let (got, whole) = (z[y * w + x], hf.z()[(y0 + y) * hf.width() + x0 + x]);
                if got.is_nan() {
                    missing += 1;
                } else {
                    assert_eq!(
                        got.to_bits(),
                        whole.to_bits(),
                        "{name} ({x0}+{x}, {y0}+{y})"
                    );
                }
            }
        }
        if (w, h) == (hf.width(), hf.height()) {
            assert_eq!(
                missing,
                hf.filled(),
                "{name}: missing cells of the whole window"
            );
        }
    }
}

#[test]
fn windows_of_every_test_geotiff_are_the_whole_readers_values() {
    let mut read = 0;
    for entry in std::fs::read_dir(data("")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "tif") {
            continue;
        }
        let name = path.display().to_string();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let windows = import::GeoTiffWindows::new(file);
        match import::load(&path) {
            Ok(hf) => {
                assert_windows_match(&name, &mut windows.unwrap(), &hf);
                assert!(import::open_file(&path).unwrap().is_some(), "{name}");
                read += 1;
            }
            // What the whole reader refuses (a codec, several bands) the windows refuse too.
            Err(e) => {
                let w = windows
                    .err()
                    .unwrap_or_else(|| panic!("{name} opened: {e}"));
                assert_eq!(w.to_string(), e.to_string());
            }
        }
    }
    assert!(read >= 6, "{read} GeoTIFFs read");
}

#[test]
fn windows_of_a_striped_tiff_and_bigtiff_are_the_whole_readers_values() {
    for big in [false, true] {
        for rows in [1, 7, 16, 70] {
            let (_, bytes) = striped(130, 70, rows, big);
            let hf = parse(&bytes).unwrap();
            let mut windows = import::GeoTiffWindows::new(Cursor::new(bytes)).unwrap();
            assert_windows_match(&format!("big {big}, {rows} rows"), &mut windows, &hf);
        }
    }
}

#[test]
fn a_window_outside_the_image_is_an_error() {
    let (_, bytes) = striped(40, 30, 8, false);
    let mut windows = import::GeoTiffWindows::new(Cursor::new(bytes)).unwrap();
    for (x0, y0, w, h) in [(0, 0, 41, 30), (39, 0, 2, 1), (0, 30, 1, 1), (0, 0, 0, 5)] {
        let err = windows.read(x0, y0, w, h).unwrap_err();
        assert!(
            err.to_string().contains("not inside the 40×30 image"),
            "{err}"
        );
    }
}

#[test]
fn a_truncated_strip_is_refused_by_the_windowed_reader() {
    for big in [false, true] {
        let (_, bytes) = striped(64, 64, 8, big);
        let cut = truncate_last_strip(&bytes, big);
        let err = import::GeoTiffWindows::new(Cursor::new(cut))
            .err()
            .expect("a truncated strip is refused");
        assert!(matches!(err, ImportError::Truncated { .. }), "{err}");
        assert!(err.to_string().contains("strip 7 of 8"), "{err}");
        // A file cut short in its data: the strip that meets the window names the cut.
        let mut short = bytes.clone();
        short.truncate(bytes.len() - 64 * 4 * 4);
        let opened = import::GeoTiffWindows::new(Cursor::new(short));
        let err = opened.err().expect("a cut file is refused");
        assert!(matches!(err, ImportError::Truncated { .. }), "{err}");
    }
}
