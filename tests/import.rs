//! Height-field import: every format, both mesh paths (exact grid, resampling), and every kind of
//! bad input as a typed error.

use paretomesh::heightfield::{Heightfield, HeightfieldError, Placement};
use paretomesh::import;
use paretomesh::import::readers::{mesh, ply, raw, stl};
use paretomesh::import::{ImportError, ImportOptions, Projection, Surface, TriangleMesh};
use rand::{RngExt, SeedableRng};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}
fn bytes(name: &str) -> Vec<u8> {
    std::fs::read(data(name)).unwrap()
}
fn defaults() -> ImportOptions {
    ImportOptions::default()
}
fn with(projection: Projection, grid_size: Option<(usize, usize)>) -> ImportOptions {
    ImportOptions {
        projection,
        grid_size,
        ..defaults()
    }
}

// ---------------------------------------------------------------- raw .f32 + .json

const SIDECAR_2X2: &[u8] = br#"{"width": 2, "height": 2}"#;
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

#[test]
fn raw_grid_loads_with_its_sidecar() {
    let hf = import::load(&data("volcano_87x61.f32")).unwrap();
    assert_eq!((hf.width(), hf.height()), (87, 61));
    assert_eq!(hf.z_range(), (94.0, 195.0));
    assert!(hf.source().contains("volcano"));
}

#[test]
fn raw_grid_errors_are_typed() {
    let grid = f32_bytes(&[1.0, 2.0, 3.0, 4.0]);
    // One value short: the file is truncated.
    let err = raw::parse(&grid[..12], SIDECAR_2X2, "t").unwrap_err();
    assert!(matches!(err, ImportError::Truncated { .. }), "{err}");
    assert!(err.to_string().contains("16 bytes"), "{err}");
    // One value too many: the sidecar's counts do not match the file.
    let five = f32_bytes(&[1.0, 2.0, 3.0, 4.0, 5.0]);
    let err = raw::parse(&five, SIDECAR_2X2, "t").unwrap_err();
    assert!(matches!(err, ImportError::WrongCount { .. }), "{err}");
    // NaN and infinity are not heights.
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let grid = f32_bytes(&[1.0, 2.0, bad, 4.0]);
        let err = raw::parse(&grid, SIDECAR_2X2, "t").unwrap_err();
        assert!(
            matches!(
                err,
                ImportError::Grid(HeightfieldError::NotFinite { index: 2 })
            ),
            "{err}"
        );
    }
    // A 1×4 strip is under 2×2.
    let err = raw::parse(&grid, br#"{"width": 1, "height": 4}"#, "t").unwrap_err();
    assert!(matches!(
        err,
        ImportError::Grid(HeightfieldError::TooSmall { .. })
    ));
    // A sidecar claiming 2^40 points is refused before any allocation.
    let err = raw::parse(&grid, br#"{"width": 1048576, "height": 1048576}"#, "t").unwrap_err();
    assert!(matches!(
        err,
        ImportError::Grid(HeightfieldError::TooLarge { .. })
    ));
    // A sidecar that is not JSON, and a missing sidecar.
    let err = raw::parse(&grid, b"{width", "t").unwrap_err();
    assert!(matches!(err, ImportError::Malformed { .. }));
    let err = import::from_bytes("a.f32", &grid, None, &defaults()).unwrap_err();
    assert!(matches!(err, ImportError::MissingSidecar { .. }));
}

// ---------------------------------------------------------------- PNG

fn encode_png(
    width: u32,
    height: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    pixels: &[u8],
    palette: Option<Vec<u8>>,
) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(color);
        encoder.set_depth(depth);
        if let Some(p) = palette {
            encoder.set_palette(p);
        }
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(pixels).unwrap();
    }
    out
}

fn png_heights(png: &[u8], terrain_rgb: bool) -> Result<Heightfield, ImportError> {
    let options = ImportOptions {
        terrain_rgb,
        ..defaults()
    };
    import::from_bytes("h.png", png, None, &options)
}

#[test]
fn png_grayscale_8_and_16_bit_are_raw_sample_values() {
    use png::{BitDepth, ColorType};
    // 3×2, row 0 = image top: heights are the samples in reading order.
    let eight = encode_png(
        3,
        2,
        ColorType::Grayscale,
        BitDepth::Eight,
        &[0, 1, 2, 100, 200, 255],
        None,
    );
    let hf = png_heights(&eight, false).unwrap();
    assert_eq!(hf.z(), &[0.0, 1.0, 2.0, 100.0, 200.0, 255.0]);
    assert!(hf.source().contains("8-bit grayscale"));
    // 16-bit samples are big-endian in the file: 0x0102 = 258, 0xFFFF = 65535.
    let sixteen = encode_png(
        2,
        2,
        ColorType::Grayscale,
        BitDepth::Sixteen,
        &[1, 2, 255, 255, 0, 0, 0, 7],
        None,
    );
    assert_eq!(
        png_heights(&sixteen, false).unwrap().z(),
        &[258.0, 65535.0, 0.0, 7.0]
    );
    // Gray + alpha: the alpha channel is ignored.
    let gray_alpha = encode_png(
        2,
        2,
        ColorType::GrayscaleAlpha,
        BitDepth::Eight,
        &[5, 0, 6, 255, 7, 9, 8, 1],
        None,
    );
    assert_eq!(
        png_heights(&gray_alpha, false).unwrap().z(),
        &[5.0, 6.0, 7.0, 8.0]
    );
}

#[test]
fn png_colour_is_luminance_and_terrain_rgb_is_an_option() {
    use png::{BitDepth, ColorType};
    // Pure red, green, blue, white: the Rec. 709 weights times 255.
    let rgb = [255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255];
    let image = encode_png(2, 2, ColorType::Rgb, BitDepth::Eight, &rgb, None);
    let hf = png_heights(&image, false).unwrap();
    let expected = [0.2126 * 255.0, 0.7152 * 255.0, 0.0722 * 255.0, 255.0];
    for (z, e) in hf.z().iter().zip(expected) {
        assert!((z - e).abs() < 1e-9, "{z} vs {e}");
    }
    assert!(hf.source().contains("luminance"));
    // Terrain-RGB: (1, 134, 160) = 100000 → 0 m; (0,0,0) → −10000 m; (1, 134, 170) → 1 m.
    let terrain = [1, 134, 160, 0, 0, 0, 1, 134, 170, 255, 255, 255];
    let image = encode_png(2, 2, ColorType::Rgb, BitDepth::Eight, &terrain, None);
    let hf = png_heights(&image, true).unwrap();
    let expected = [0.0, -10000.0, 1.0, -10000.0 + 16_777_215.0 * 0.1];
    for (z, e) in hf.z().iter().zip(expected) {
        assert!((z - e).abs() < 1e-6, "{z} vs {e}");
    }
    // Palette images are expanded to RGB, then read as luminance.
    let palette = encode_png(
        2,
        2,
        ColorType::Indexed,
        BitDepth::Eight,
        &[0, 1, 1, 0],
        Some(vec![0, 0, 0, 255, 255, 255]),
    );
    let hf = png_heights(&palette, false).unwrap();
    for (z, e) in hf.z().iter().zip([0.0, 255.0, 255.0, 0.0]) {
        assert!((z - e).abs() < 1e-9, "{z} vs {e}");
    }
    // Terrain-RGB on a grayscale image is a wrong option, not a silent misreading.
    let gray = encode_png(2, 2, ColorType::Grayscale, BitDepth::Eight, &[0; 4], None);
    assert!(matches!(
        png_heights(&gray, true),
        Err(ImportError::BadOption { .. })
    ));
}

#[test]
fn png_bad_input_is_a_typed_error() {
    use png::{BitDepth, ColorType};
    let good = encode_png(4, 4, ColorType::Grayscale, BitDepth::Eight, &[9; 16], None);
    // Cut inside the image data: truncated (or malformed where the cut lands in a chunk header).
    let err = png_heights(&good[..good.len() - 20], false).unwrap_err();
    assert!(
        matches!(
            err,
            ImportError::Truncated { .. } | ImportError::Malformed { .. }
        ),
        "{err}"
    );
    // Not a PNG at all.
    assert!(matches!(
        png_heights(b"hello", false),
        Err(ImportError::Malformed { .. })
    ));
    // A 1-pixel-wide image is under 2×2.
    let strip = encode_png(1, 5, ColorType::Grayscale, BitDepth::Eight, &[0; 5], None);
    assert!(matches!(
        png_heights(&strip, false),
        Err(ImportError::Grid(HeightfieldError::TooSmall { .. }))
    ));
    // Wider than MAX_SIDE: refused from the header, before the pixels are decoded.
    let wide = encode_png(
        16_385,
        2,
        ColorType::Grayscale,
        BitDepth::Eight,
        &vec![0; 32_770],
        None,
    );
    assert!(matches!(
        png_heights(&wide, false),
        Err(ImportError::Grid(HeightfieldError::TooLarge { .. }))
    ));
}

// ---------------------------------------------------------------- PLY

#[test]
fn grid_plys_are_used_exactly_and_match_the_raw_grid_bit_for_bit() {
    for name in ["volcano_87x61", "bunny_33x33"] {
        let from_ply = import::load(&data(&format!("{name}.ply"))).unwrap();
        let from_raw = import::load(&data(&format!("{name}.f32"))).unwrap();
        assert_eq!(
            (from_ply.width(), from_ply.height()),
            (from_raw.width(), from_raw.height())
        );
        let same = from_ply
            .z()
            .iter()
            .zip(from_raw.z())
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "{name}: PLY heights differ from the .f32 grid");
        assert_eq!(from_ply.placement(), &Placement::Grid);
        assert_eq!(from_ply.filled(), 0);
        assert!(!from_ply.resampled(), "read as is, not resampled");
        assert!(!from_raw.resampled());
        assert!(from_ply.source().contains("exact"), "{}", from_ply.source());
    }
}

#[test]
fn a_grid_ply_asked_for_another_size_is_resampled_in_its_own_plane() {
    // 87×61 → 44×31 halves the resolution exactly (spacing 2), so every grid point is a vertex of
    // the PLY and keeps its height; the placement maps it back onto that vertex.
    let options = with(Projection::Auto, Some((44, 31)));
    let hf = import::load_with(&data("volcano_87x61.ply"), &options).unwrap();
    let raw = import::load(&data("volcano_87x61.f32")).unwrap();
    assert_eq!(hf.spacing(), [2.0, 2.0]);
    assert!(
        hf.resampled(),
        "another size means resampling, even in the grid's own plane"
    );
    for y in 0..31 {
        for x in 0..44 {
            let (z, expected) = (hf.z_at(x, y), raw.z_at(2 * x, 2 * y));
            assert!((z - expected).abs() < 1e-9, "({x},{y}): {z} vs {expected}");
            let world = hf.to_world(hf.index(x, y), z);
            let want = [2.0 * x as f64, 2.0 * y as f64, expected];
            assert!(
                (0..3).all(|k| (world[k] - want[k]).abs() < 1e-9),
                "{world:?} vs {want:?}"
            );
        }
    }
    assert!(
        hf.source().contains("exact 87×61 grid, resampled"),
        "{}",
        hf.source()
    );
}

/// Writes a mesh as binary PLY (float x y z, uchar-counted int index lists).
fn binary_ply(mesh: &TriangleMesh, big_endian: bool) -> Vec<u8> {
    let order = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = format!(
        "ply\nformat {order} 1.0\ncomment test\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.vertices.len(),
        mesh.triangles.len()
    )
    .into_bytes();
    let f = |v: f32| {
        if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let i = |v: i32| {
        if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    for p in &mesh.vertices {
        for c in p {
            out.extend(f(*c as f32));
        }
    }
    for t in &mesh.triangles {
        out.push(3);
        for c in t {
            out.extend(i(*c as i32));
        }
    }
    out
}

#[test]
fn binary_plys_of_both_byte_orders_read_like_the_ascii_one() {
    let ascii = ply::parse(&bytes("volcano_87x61.ply")).unwrap();
    for big_endian in [false, true] {
        let binary = ply::parse(&binary_ply(&ascii, big_endian)).unwrap();
        assert_eq!(binary, ascii, "big_endian = {big_endian}");
    }
}

const PLY_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

#[test]
fn ply_bad_input_is_a_typed_error() {
    let ok = format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    assert!(ply::parse(ok.as_bytes()).is_ok());
    // Truncated: the file ends before the face.
    let cut = format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n");
    assert!(matches!(
        ply::parse(cut.as_bytes()),
        Err(ImportError::Truncated { .. })
    ));
    // Truncated binary: the last index is cut.
    let mesh = ply::parse(ok.as_bytes()).unwrap();
    let bin = binary_ply(&mesh, false);
    assert!(matches!(
        ply::parse(&bin[..bin.len() - 2]),
        Err(ImportError::Truncated { .. })
    ));
    // Wrong count: two faces in a file whose header declares one.
    let extra = format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n");
    assert!(matches!(
        ply::parse(extra.as_bytes()),
        Err(ImportError::WrongCount { .. })
    ));
    // Wrong count: the header says 3 vertices but there are 4, so a vertex line is read as a face.
    let shifted = format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n");
    assert!(matches!(
        ply::parse(shifted.as_bytes()),
        Err(ImportError::WrongCount { .. })
    ));
    // NaN and infinite coordinates.
    for bad in ["nan", "inf"] {
        let text = format!("{PLY_HEAD}0 0 0\n1 {bad} 0\n0 1 0\n3 0 1 2\n");
        let err = ply::parse(text.as_bytes()).unwrap_err();
        assert!(matches!(err, ImportError::NotFinite { .. }), "{err}");
        assert!(err.to_string().contains("vertex 1"), "{err}");
    }
    // An index past the last vertex.
    let far = format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    assert!(matches!(
        ply::parse(far.as_bytes()),
        Err(ImportError::Malformed { .. })
    ));
    // Empty: no vertices at all.
    let empty = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    assert!(matches!(
        ply::parse(empty.as_bytes()),
        Err(ImportError::EmptyMesh { .. })
    ));
    // Over the limit: 2^24 + 1 vertices and 2^25 + 1 faces claimed.
    let many = PLY_HEAD.replace("vertex 3", "vertex 16777217");
    assert!(matches!(
        ply::parse(many.as_bytes()),
        Err(ImportError::OverLimit {
            what: "vertices",
            ..
        })
    ));
    let many = PLY_HEAD.replace("face 1", "face 33554433");
    assert!(matches!(
        ply::parse(many.as_bytes()),
        Err(ImportError::OverLimit {
            what: "triangles",
            ..
        })
    ));
    // Under the limit but more than the file can hold: refused before allocating.
    let big = PLY_HEAD.replace("vertex 3", "vertex 1000000");
    let err = ply::parse(format!("{big}0 0 0\n").as_bytes()).unwrap_err();
    assert!(matches!(err, ImportError::Truncated { .. }), "{err}");
    // No end_header, and not a PLY.
    assert!(matches!(
        ply::parse(b"ply\nformat ascii 1.0\n"),
        Err(ImportError::Truncated { .. })
    ));
    assert!(matches!(
        ply::parse(b"PK\x03\x04"),
        Err(ImportError::Malformed { .. })
    ));
}

// ---------------------------------------------------------------- OBJ

#[test]
fn obj_grid_is_used_exactly_and_bad_obj_is_an_error() {
    // A 3×2 grid with z = x + 10·y, as two rows of quads.
    let text = "v 0 0 0\nv 1 0 1\nv 2 0 2\nv 0 1 10\nv 1 1 11\nv 2 1 12\nf 1 2 5 4\nf 2 3 6 5\n";
    let hf = import::from_bytes("g.obj", text.as_bytes(), None, &defaults()).unwrap();
    assert_eq!((hf.width(), hf.height()), (3, 2));
    assert_eq!(hf.z(), &[0.0, 1.0, 2.0, 10.0, 11.0, 12.0]);
    let opts = defaults();
    let bad = |t: &str| import::from_bytes("b.obj", t.as_bytes(), None, &opts).unwrap_err();
    assert!(matches!(
        bad("v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ImportError::NotFinite { .. }
    ));
    assert!(matches!(
        bad("v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
        ImportError::EmptyMesh { .. }
    ));
    assert!(matches!(
        bad("v 0 0 0\nf 1 2 3\n"),
        ImportError::Malformed { .. }
    ));
    assert!(matches!(
        bad("v 0 zero 0\nf 1 1 1\n"),
        ImportError::Malformed { .. }
    ));
}

// ---------------------------------------------------------------- STL

/// Writes triangles as binary STL, with `header` at the start of the 80-byte header.
fn binary_stl(triangles: &[[[f32; 3]; 3]], header: &[u8]) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out[..header.len()].copy_from_slice(header);
    out.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        out.extend([0u8; 12]);
        for p in t {
            for c in p {
                out.extend(c.to_le_bytes());
            }
        }
        out.extend([0u8; 2]);
    }
    out
}

fn ascii_stl(triangles: &[[[f32; 3]; 3]]) -> String {
    let mut s = String::from("solid t\n");
    for t in triangles {
        s.push_str("facet normal 0 0 1\n outer loop\n");
        for p in t {
            s.push_str(&format!("  vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        s.push_str(" endloop\nendfacet\n");
    }
    s.push_str("endsolid t\n");
    s
}

/// Two triangles of the unit square with z = x + 2y: its corners form a 2×2 grid.
const SQUARE: [[[f32; 3]; 3]; 2] = [
    [[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [1.0, 1.0, 3.0]],
    [[0.0, 0.0, 0.0], [1.0, 1.0, 3.0], [0.0, 1.0, 2.0]],
];

#[test]
fn stl_binary_and_ascii_agree_and_merge_shared_corners() {
    let ascii = stl::parse(ascii_stl(&SQUARE).as_bytes()).unwrap();
    let binary = stl::parse(&binary_stl(&SQUARE, b"")).unwrap();
    // A binary file whose header starts with "solid " (as some exporters write) is still binary.
    let solid_header = stl::parse(&binary_stl(&SQUARE, b"solid exported")).unwrap();
    assert_eq!(ascii, binary);
    assert_eq!(binary, solid_header);
    assert_eq!(binary.vertices.len(), 4);
    assert_eq!(binary.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    let hf = import::from_bytes("s.stl", &binary_stl(&SQUARE, b""), None, &defaults()).unwrap();
    assert_eq!(hf.z(), &[0.0, 1.0, 2.0, 3.0]);
}

#[test]
fn stl_bad_input_is_a_typed_error() {
    let good = binary_stl(&SQUARE, b"");
    assert!(matches!(
        stl::parse(&good[..good.len() - 1]),
        Err(ImportError::Truncated { .. })
    ));
    assert!(matches!(
        stl::parse(&good[..50]),
        Err(ImportError::Truncated { .. })
    ));
    let mut longer = good.clone();
    longer.extend([0u8; 50]);
    longer[80] = 2; // still claims 2 triangles, but holds 3
    assert!(matches!(
        stl::parse(&longer),
        Err(ImportError::WrongCount { .. })
    ));
    let mut nan = SQUARE;
    nan[1][2][1] = f32::NAN;
    assert!(matches!(
        stl::parse(&binary_stl(&nan, b"")),
        Err(ImportError::NotFinite { .. })
    ));
    assert!(matches!(
        stl::parse(&binary_stl(&[], b"")),
        Err(ImportError::EmptyMesh { .. })
    ));
    // 2^25 + 1 triangles claimed in an 84-byte file.
    let mut claim = binary_stl(&[], b"");
    claim[80..84].copy_from_slice(&(33_554_433u32).to_le_bytes());
    assert!(matches!(
        stl::parse(&claim),
        Err(ImportError::OverLimit {
            what: "triangles",
            ..
        })
    ));
    // ASCII: cut inside a facet; a facet with two vertices; inf; no facets.
    let text = ascii_stl(&SQUARE);
    let cut = &text[..text.find("endloop").unwrap()];
    assert!(matches!(
        stl::parse(cut.as_bytes()),
        Err(ImportError::Truncated { .. })
    ));
    let two = text.replacen("  vertex 1 0 1\n", "", 1);
    assert!(matches!(
        stl::parse(two.as_bytes()),
        Err(ImportError::WrongCount { .. })
    ));
    let inf = text.replacen("vertex 1 0 1", "vertex 1 0 inf", 1);
    assert!(matches!(
        stl::parse(inf.as_bytes()),
        Err(ImportError::NotFinite { .. })
    ));
    assert!(matches!(
        stl::parse(b"solid x\nendsolid x\n"),
        Err(ImportError::EmptyMesh { .. })
    ));
}

// ---------------------------------------------------------------- resampling

fn rotate(p: [f64; 3], yaw: f64, tilt: f64) -> [f64; 3] {
    let (sy, cy) = yaw.sin_cos();
    let (st, ct) = tilt.sin_cos();
    let q = [cy * p[0] - sy * p[1], sy * p[0] + cy * p[1], p[2]];
    [q[0], ct * q[1] - st * q[2], st * q[1] + ct * q[2]]
}

/// A `w`×`h` lattice mesh (two triangles per cell) with heights `f(x, y)`, then moved by `map`.
fn lattice_mesh(
    w: usize,
    h: usize,
    f: impl Fn(f64, f64) -> f64,
    map: impl Fn([f64; 3]) -> [f64; 3],
) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for y in 0..h {
        for x in 0..w {
            m.vertices
                .push(map([x as f64, y as f64, f(x as f64, y as f64)]));
        }
    }
    for y in 0..h - 1 {
        for x in 0..w - 1 {
            let i = (y * w + x) as u32;
            let (r, d) = (1, w as u32);
            m.triangles.push([i, i + r, i + d + r]);
            m.triangles.push([i, i + d + r, i + d]);
        }
    }
    m
}

fn resampled(mesh: &TriangleMesh, options: &ImportOptions) -> Result<Heightfield, ImportError> {
    mesh::to_heightfield(mesh, "test", "mesh", options)
}

/// Every vertex must equal `to_world` of some grid point at that point's height.
fn assert_vertices_map_back(mesh: &TriangleMesh, hf: &Heightfield, tolerance: f64) {
    for v in &mesh.vertices {
        let best = (0..hf.len() as u32)
            .map(|i| {
                let p = hf.to_world(i, hf.z()[i as usize]);
                (0..3).map(|k| (p[k] - v[k]).abs()).fold(0.0, f64::max)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            best < tolerance,
            "vertex {v:?} is {best} from every grid point"
        );
    }
}

#[test]
fn planar_resampling_maps_grid_points_back_to_the_vertices() {
    // A flat 5×3 lattice rotated and tilted in space: no longer a grid in (x, y), so it is
    // resampled; on a 9×5 grid every vertex lands on a grid point and must map back to itself.
    let mesh = lattice_mesh(
        5,
        3,
        |_, _| 0.0,
        |p| {
            let q = rotate(p, 0.4, 0.7);
            [q[0] + 10.0, q[1] - 3.0, q[2] + 2.0]
        },
    );
    let hf = resampled(&mesh, &with(Projection::Auto, Some((9, 5)))).unwrap();
    assert!(matches!(hf.placement(), Placement::Planar { .. }));
    assert!(hf.resampled());
    assert_eq!((hf.width(), hf.height()), (9, 5));
    assert_eq!(hf.filled(), 0);
    assert_vertices_map_back(&mesh, &hf, 1e-9);
    // Flat in its own plane: every height is 0 (up to rounding).
    assert!(hf.z().iter().all(|z| z.abs() < 1e-9));
}

#[test]
fn planar_resampling_of_a_tilted_bump_keeps_its_heights() {
    // A bump z = 4 − (x−4)² / 4 … on a 9×9 lattice, tilted: projected back along the best-fit
    // normal, the bump's vertices lie on the grid of the same size and map back to themselves.
    let mesh = lattice_mesh(
        9,
        9,
        |x, y| 2.0 * (-((x - 4.0).powi(2) + (y - 4.0).powi(2)) / 8.0).exp(),
        |p| rotate(p, 0.0, 0.3),
    );
    let hf = resampled(&mesh, &with(Projection::Planar, Some((9, 9)))).unwrap();
    assert_vertices_map_back(&mesh, &hf, 1e-6);
}

#[test]
fn holes_are_filled_from_the_nearest_value_and_counted() {
    // A 7×7 lattice on a tilted plane with the triangles around the centre vertex removed.
    let mut mesh = lattice_mesh(7, 7, |x, _| x, |p| p);
    let centre = 3 * 7 + 3;
    mesh.triangles.retain(|t| !t.contains(&(centre as u32)));
    // Explicit planar: the lattice path would use the vertices as they are.
    let hf = resampled(&mesh, &with(Projection::Planar, Some((13, 13)))).unwrap();
    // The 6 removed triangles form the hexagon (2,2) (3,2) (4,3) (4,4) (3,4) (2,3) around vertex
    // (3,3); on the 13×13 grid (half the lattice step) 7 grid points lie strictly inside it.
    assert_eq!(hf.filled(), 7, "{}", hf.source());
    assert!(hf.source().contains("7 grid points"));
    assert!(hf.z().iter().all(|z| z.is_finite()));
}

fn uv_sphere(rings: usize, segments: usize, radius: f64) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    m.vertices.push([0.0, 0.0, radius]);
    for r in 1..rings {
        let phi = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let theta = std::f64::consts::TAU * s as f64 / segments as f64;
            m.vertices.push([
                radius * phi.sin() * theta.cos(),
                radius * phi.sin() * theta.sin(),
                radius * phi.cos(),
            ]);
        }
    }
    m.vertices.push([0.0, 0.0, -radius]);
    let ring = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
    let bottom = (m.vertices.len() - 1) as u32;
    for s in 0..segments {
        m.triangles.push([0, ring(1, s), ring(1, s + 1)]);
        m.triangles
            .push([bottom, ring(rings - 1, s + 1), ring(rings - 1, s)]);
        for r in 1..rings - 1 {
            m.triangles
                .push([ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)]);
            m.triangles
                .push([ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)]);
        }
    }
    m
}

#[test]
fn a_closed_sphere_has_no_planar_projection_but_unwraps_cylindrically() {
    // Planar: front and back cover the same disc, so nearly every covered point is covered twice.
    let sphere = uv_sphere(12, 24, 2.0);
    let err = resampled(&sphere, &with(Projection::Planar, Some((33, 33)))).unwrap_err();
    match &err {
        ImportError::NoProjection { tried } => {
            assert_eq!(tried.len(), 1);
            assert_eq!(tried[0].0, Projection::Planar);
        }
        other => panic!("expected NoProjection, got {other}"),
    }
    assert!(err.to_string().contains("planar"), "{err}");
    // Auto falls back to the cylindrical unwrap, where a sphere is single-valued: ρ(θ, ζ).
    let hf = resampled(&sphere, &with(Projection::Auto, Some((48, 24)))).unwrap();
    assert!(matches!(hf.placement(), Placement::Cylindrical { .. }));
    assert!(hf.source().contains("cylindrical"));
    assert!(
        hf.source().contains("the planar projection folds"),
        "{}",
        hf.source()
    );
    // Every radius is at most the sphere's.
    assert!(hf.z().iter().all(|&z| z <= 2.0 + 1e-9));
}

/// Outer radius of the test bust at angle θ and height ζ: a wavy, bulging column.
fn bust_radius(theta: f64, zeta: f64) -> f64 {
    1.0 + 0.1 * (3.0 * theta).sin() + 0.08 * (std::f64::consts::FRAC_PI_4 * zeta).cos()
}

/// A closed, thick bust along z (ζ from −2 to 2): an outer wall of radius `bust_radius`, an
/// inner wall 5 % of the radius inside it, wound the other way, and flat annular caps joining
/// them at both ends, as a printable shell is.
fn thick_bust(angles: usize, rows: usize) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for wall in [1.0, 0.95] {
        for r in 0..rows {
            let zeta = -2.0 + 4.0 * r as f64 / (rows - 1) as f64;
            for a in 0..angles {
                let theta = std::f64::consts::TAU * a as f64 / angles as f64;
                let rho = wall * bust_radius(theta, zeta);
                m.vertices
                    .push([rho * theta.cos(), rho * theta.sin(), zeta]);
            }
        }
    }
    let at =
        |wall: usize, r: usize, a: usize| (wall * rows * angles + r * angles + a % angles) as u32;
    for a in 0..angles {
        for r in 0..rows - 1 {
            // Outer wall faces out, inner wall faces in (towards the axis).
            m.triangles
                .push([at(0, r, a), at(0, r, a + 1), at(0, r + 1, a + 1)]);
            m.triangles
                .push([at(0, r, a), at(0, r + 1, a + 1), at(0, r + 1, a)]);
            m.triangles
                .push([at(1, r, a), at(1, r + 1, a + 1), at(1, r, a + 1)]);
            m.triangles
                .push([at(1, r, a), at(1, r + 1, a), at(1, r + 1, a + 1)]);
        }
        for (r, flip) in [(0, true), (rows - 1, false)] {
            let (o0, o1, i0, i1) = (at(0, r, a), at(0, r, a + 1), at(1, r, a), at(1, r, a + 1));
            let (t0, t1) = ([o0, o1, i1], [o0, i1, i0]);
            if flip {
                m.triangles.push([t0[0], t0[2], t0[1]]);
                m.triangles.push([t1[0], t1[2], t1[1]]);
            } else {
                m.triangles.push(t0);
                m.triangles.push(t1);
            }
        }
    }
    m
}

#[test]
fn a_closed_thick_bust_imports_as_its_outer_surface() {
    let bust = thick_bust(96, 41);
    // As a single surface every projection folds, and the message points to the outer surface.
    for projection in [Projection::Auto, Projection::Cylindrical] {
        let err = resampled(&bust, &with(projection, Some((128, 64)))).unwrap_err();
        assert!(matches!(err, ImportError::NoProjection { .. }), "{err}");
        let message = err.to_string();
        assert!(message.contains("folds over itself"), "{message}");
        assert!(message.contains("--surface outer"), "{message}");
    }
    for projection in [Projection::Auto, Projection::Cylindrical] {
        let options = ImportOptions {
            surface: Surface::Outer,
            ..with(projection, Some((128, 64)))
        };
        let hf = resampled(&bust, &options).unwrap();
        assert!(matches!(hf.placement(), Placement::Cylindrical { .. }));
        assert_eq!((hf.width(), hf.height()), (128, 64));
        // Every grid point lies on the outer wall: its radius within 1 % of the analytic one.
        for i in 0..hf.len() as u32 {
            let p = hf.to_world(i, hf.z()[i as usize]);
            let rho = p[0].hypot(p[1]);
            let want = bust_radius(p[1].atan2(p[0]), p[2]);
            assert!(
                (rho - want).abs() <= 0.01 * want,
                "grid point {i}: radius {rho}, the outer wall's is {want}"
            );
        }
        // The report counts the points taken from the outer wall and the share covered twice.
        let source = hf.source();
        let counted: usize = source
            .split("outer surface: ")
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no outer-surface count in: {source}"));
        assert!(counted > hf.len() / 2, "{source}");
        assert!(source.contains("covered more than once"), "{source}");
    }
}

#[test]
fn the_outer_surface_of_a_closed_slab_is_its_top() {
    // A closed terrain block: a bumpy top over 4 × 3, a flat bottom at z = −0.5, side walls.
    let (nx, ny) = (21usize, 16usize);
    let top = |x: f64, y: f64| 0.3 * (x * 1.3).sin() * (y * 0.9).cos();
    let mut m = TriangleMesh::default();
    for level in 0..2 {
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (
                    4.0 * i as f64 / (nx - 1) as f64,
                    3.0 * j as f64 / (ny - 1) as f64,
                );
                m.vertices
                    .push([x, y, if level == 0 { top(x, y) } else { -0.5 }]);
            }
        }
    }
    let at = |level: usize, i: usize, j: usize| (level * nx * ny + j * nx + i) as u32;
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            m.triangles
                .push([at(0, i, j), at(0, i + 1, j), at(0, i + 1, j + 1)]);
            m.triangles
                .push([at(0, i, j), at(0, i + 1, j + 1), at(0, i, j + 1)]);
            m.triangles
                .push([at(1, i, j), at(1, i + 1, j + 1), at(1, i + 1, j)]);
            m.triangles
                .push([at(1, i, j), at(1, i, j + 1), at(1, i + 1, j + 1)]);
        }
    }
    // Side walls along the four edges.
    let mut ring: Vec<(usize, usize)> = (0..nx).map(|i| (i, 0)).collect();
    ring.extend((1..ny).map(|j| (nx - 1, j)));
    ring.extend((0..nx - 1).rev().map(|i| (i, ny - 1)));
    ring.extend((1..ny - 1).rev().map(|j| (0, j)));
    for k in 0..ring.len() {
        let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
        m.triangles
            .push([at(0, a.0, a.1), at(1, a.0, a.1), at(1, b.0, b.1)]);
        m.triangles
            .push([at(0, a.0, a.1), at(1, b.0, b.1), at(0, b.0, b.1)]);
    }
    // Seen along z, top and bottom cover the same rectangle: a single surface is refused.
    let single = resampled(&m, &with(Projection::Planar, Some((41, 31))));
    assert!(matches!(single, Err(ImportError::NoProjection { .. })));
    let options = ImportOptions {
        surface: Surface::Outer,
        ..with(Projection::Planar, Some((41, 31)))
    };
    let hf = resampled(&m, &options).unwrap();
    assert!(
        matches!(hf.placement(), Placement::Planar { .. }),
        "{}",
        hf.source()
    );
    // Seen from above: every grid point inside the rim is on the top, none on the bottom. (On
    // the rim the side walls are edge-on, and the PCA normal leans a little with the bumps.)
    let bad: Vec<[f64; 3]> = (0..hf.len() as u32)
        .filter(|&i| {
            let (x, y) = hf.coords(i);
            x > 0 && y > 0 && x + 1 < hf.width() && y + 1 < hf.height()
        })
        .map(|i| hf.to_world(i, hf.z()[i as usize]))
        .filter(|p| (p[2] - top(p[0], p[1])).abs() >= 0.02)
        .collect();
    assert!(
        bad.is_empty(),
        "{} points off the top: {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    assert!(hf.source().contains("outer surface"), "{}", hf.source());
}

#[test]
fn cylindrical_unwrap_maps_grid_points_back_to_the_vertices() {
    // A closed tube of radius 3 and length 8 along x (its longest extent, so the unwrap axis,
    // through the mean, which is on the tube's axis): 16 angles × 5 lengths. The seam falls
    // between two angles, so a 16×5 grid puts every vertex on a grid point.
    let mut mesh = TriangleMesh::default();
    for j in 0..5 {
        for i in 0..16 {
            let a = std::f64::consts::TAU * i as f64 / 16.0;
            mesh.vertices
                .push([2.0 * j as f64, 3.0 * a.cos(), 3.0 * a.sin()]);
        }
    }
    for j in 0..4u32 {
        for i in 0..16u32 {
            let (v, next) = (j * 16 + i, j * 16 + (i + 1) % 16);
            mesh.triangles.push([v, next, next + 16]);
            mesh.triangles.push([v, next + 16, v + 16]);
        }
    }
    let hf = resampled(&mesh, &with(Projection::Cylindrical, Some((16, 5)))).unwrap();
    assert!(matches!(hf.placement(), Placement::Cylindrical { .. }));
    assert_eq!(hf.filled(), 0);
    assert_vertices_map_back(&mesh, &hf, 1e-9);
    // Between the vertices the chords are inside the circle: every radius is at most 3.
    assert!(hf.z().iter().all(|&z| z <= 3.0 + 1e-9));
}

fn torus(major: f64, minor: f64, n: usize, m: usize) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for i in 0..n {
        let u = std::f64::consts::TAU * i as f64 / n as f64;
        for j in 0..m {
            let v = std::f64::consts::TAU * j as f64 / m as f64;
            let r = major + minor * v.cos();
            mesh.vertices
                .push([r * u.cos(), r * u.sin(), minor * v.sin()]);
        }
    }
    let at = |i: usize, j: usize| ((i % n) * m + j % m) as u32;
    for i in 0..n {
        for j in 0..m {
            mesh.triangles
                .push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            mesh.triangles
                .push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    mesh
}

#[test]
fn a_torus_folds_in_every_projection() {
    // Planar: top and bottom halves overlap. Cylindrical: rays from the axis cross the tube twice.
    let err = resampled(
        &torus(3.0, 1.0, 48, 24),
        &with(Projection::Auto, Some((64, 64))),
    )
    .unwrap_err();
    match &err {
        ImportError::NoProjection { tried } => {
            let names: Vec<Projection> = tried.iter().map(|t| t.0).collect();
            assert_eq!(names, [Projection::Planar, Projection::Cylindrical]);
            assert!(tried.iter().all(|t| t.1.is_some_and(|o| o > 0.1)), "{err}");
        }
        other => panic!("expected NoProjection, got {other}"),
    }
    let message = err.to_string();
    assert!(
        message.contains("planar") && message.contains("cylindrical"),
        "{message}"
    );
}

#[test]
fn a_rolled_up_sheet_folds_in_every_projection() {
    // A sheet rolled up like a carpet: a spiral of radius 1 → 3 over two turns, 10 long. Every
    // plane sees several layers, and so does every ray from the roll's axis.
    let mut mesh = TriangleMesh::default();
    let (turns, steps) = (2.0, 64);
    for k in 0..=steps {
        let t = k as f64 / steps as f64;
        let a = std::f64::consts::TAU * turns * t;
        let r = 1.0 + 2.0 * t;
        for y in 0..6 {
            mesh.vertices
                .push([r * a.cos(), 2.0 * y as f64, r * a.sin()]);
        }
    }
    for k in 0..steps as u32 {
        for y in 0..5u32 {
            let a = k * 6 + y;
            mesh.triangles.push([a, a + 6, a + 7]);
            mesh.triangles.push([a, a + 7, a + 1]);
        }
    }
    let err = resampled(&mesh, &with(Projection::Auto, Some((40, 40)))).unwrap_err();
    match &err {
        ImportError::NoProjection { tried } => assert_eq!(tried.len(), 2, "{err}"),
        other => panic!("expected NoProjection, got {other}"),
    }
}

#[test]
fn grid_size_limits_and_degenerate_meshes_are_errors() {
    let mesh = lattice_mesh(3, 3, |x, y| x * y, |p| rotate(p, 0.2, 0.2));
    let err = resampled(&mesh, &with(Projection::Planar, Some((1, 5)))).unwrap_err();
    assert!(
        matches!(err, ImportError::Grid(HeightfieldError::TooSmall { .. })),
        "{err}"
    );
    let err = resampled(&mesh, &with(Projection::Planar, Some((16_385, 2)))).unwrap_err();
    assert!(
        matches!(err, ImportError::Grid(HeightfieldError::TooLarge { .. })),
        "{err}"
    );
    // All vertices on one line: no triangle has any area.
    let line = TriangleMesh {
        vertices: vec![[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
        triangles: vec![[0, 1, 2]],
    };
    assert!(matches!(
        resampled(&line, &defaults()),
        Err(ImportError::EmptyMesh { .. })
    ));
}

#[test]
fn automatic_grid_size_follows_the_vertex_count_and_the_cap() {
    // 20×5 vertices (100) over a 19×4 extent: about 100 grid points with the extent's aspect.
    let mesh = lattice_mesh(20, 5, |x, _| 0.1 * x, |p| rotate(p, 0.3, 0.0));
    let hf = resampled(&mesh, &with(Projection::Planar, None)).unwrap();
    let n = hf.width() * hf.height();
    assert!((80..=120).contains(&n), "{}×{}", hf.width(), hf.height());
    assert!(hf.width() > hf.height());
}

// ---------------------------------------------------------------- dispatch and robustness

#[test]
fn unknown_files_and_options_are_errors() {
    let err = import::from_bytes("notes.txt", b"hello", None, &defaults()).unwrap_err();
    assert!(matches!(err, ImportError::UnknownFormat { .. }));
    // A PLY without the extension is recognised by its magic bytes.
    let ply_bytes = bytes("bunny_33x33.ply");
    assert!(import::from_bytes("upload", &ply_bytes, None, &defaults()).is_ok());
    let terrain = ImportOptions {
        terrain_rgb: true,
        ..defaults()
    };
    let err = import::from_bytes("a.ply", &ply_bytes, None, &terrain).unwrap_err();
    assert!(matches!(err, ImportError::BadOption { .. }));
    let err = import::load(&data("does_not_exist.ply")).unwrap_err();
    assert!(matches!(err, ImportError::Io { .. }));
}

#[test]
fn random_and_damaged_bytes_never_panic() {
    // Seeded: the same bytes every run. Each parser gets random bytes, every prefix length of a
    // valid file at a stride, and valid files with random bytes overwritten.
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
    let small_ply = format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes();
    let valid: Vec<(&str, Vec<u8>)> = vec![
        ("a.ply", small_ply.clone()),
        ("a.ply", binary_ply(&ply::parse(&small_ply).unwrap(), false)),
        ("a.ply", binary_ply(&ply::parse(&small_ply).unwrap(), true)),
        ("a.stl", binary_stl(&SQUARE, b"")),
        ("a.stl", ascii_stl(&SQUARE).into_bytes()),
        (
            "a.obj",
            b"v 0 0 0\nv 1 0 1\nv 0 1 2\nv 1 1 3\nf 1 2 4 3\n".to_vec(),
        ),
        (
            "a.png",
            encode_png(
                3,
                3,
                png::ColorType::Rgb,
                png::BitDepth::Eight,
                &[7; 27],
                None,
            ),
        ),
        ("a.f32", f32_bytes(&[1.0, 2.0, 3.0, 4.0])),
    ];
    let options = [defaults(), with(Projection::Cylindrical, Some((5, 5)))];
    let mut inputs: Vec<(&str, Vec<u8>)> = Vec::new();
    for (name, good) in &valid {
        for len in (0..good.len()).step_by(3) {
            inputs.push((name, good[..len].to_vec()));
        }
        for _ in 0..40 {
            let mut damaged = good.clone();
            for _ in 0..rng.random_range(1..4) {
                let at = rng.random_range(0..damaged.len());
                damaged[at] = rng.random::<u8>();
            }
            inputs.push((name, damaged));
        }
        for _ in 0..10 {
            let len = rng.random_range(0..300);
            inputs.push((name, (0..len).map(|_| rng.random::<u8>()).collect()));
        }
    }
    for (name, input) in &inputs {
        for opts in &options {
            // Only the absence of a panic is checked: any Ok or Err is acceptable here.
            let _ = import::from_bytes(name, input, Some(SIDECAR_2X2), opts);
        }
    }
}
