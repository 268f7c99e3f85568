//! The .glb writer, read back with the `gltf` crate: positions, normals, indices and colours.

use paretomesh::export::{GlbError, GlbMesh, VertexColors, vertex_normals, write_glb};

/// A 3×2 grid of points lifted by z = x·y + offset, as two rows of triangles.
fn patch(offset: [f64; 3]) -> (Vec<[f64; 3]>, Vec<u32>) {
    let positions = (0..6)
        .map(|i| {
            let (x, y) = ((i % 3) as f64, (i / 3) as f64);
            [x + offset[0], y + offset[1], x * y * 0.5 + offset[2]]
        })
        .collect();
    (positions, vec![0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4])
}

struct ReadBack {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    indices: Vec<u32>,
    colors: Option<Vec<[u8; 4]>>,
    translation: [f32; 3],
    double_sided: bool,
}

fn read_back(bytes: &[u8]) -> ReadBack {
    let file = gltf::Gltf::from_slice(bytes).expect("a valid .glb");
    assert_eq!(file.meshes().count(), 1);
    let mesh = file.meshes().next().unwrap();
    assert_eq!(mesh.primitives().count(), 1);
    let primitive = mesh.primitives().next().unwrap();
    assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
    let blob = file.blob.as_deref();
    let reader = primitive.reader(|buffer| match buffer.source() {
        gltf::buffer::Source::Bin => blob,
        _ => None,
    });
    let node = file.nodes().next().unwrap();
    assert_eq!(node.mesh().map(|m| m.index()), Some(0));
    ReadBack {
        positions: reader.read_positions().unwrap().collect(),
        normals: reader.read_normals().unwrap().collect(),
        indices: reader.read_indices().unwrap().into_u32().collect(),
        colors: reader.read_colors(0).map(|c| c.into_rgba_u8().collect()),
        translation: node.transform().decomposed().0,
        double_sided: primitive.material().double_sided(),
    }
}

#[test]
fn positions_normals_and_indices_read_back() {
    let (positions, indices) = patch([0.0; 3]);
    let normals = vertex_normals(&positions, &indices);
    let bytes = write_glb(&GlbMesh {
        positions: &positions,
        normals: &normals,
        indices: &indices,
        colors: None,
    })
    .unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(bytes.len() % 4, 0);
    let back = read_back(&bytes);
    assert_eq!(back.indices, indices);
    assert_eq!(back.colors, None);
    assert!(back.double_sided);
    // Stored relative to the bounding box centre, which is the node's translation.
    for (p, q) in positions.iter().zip(&back.positions) {
        for k in 0..3 {
            let world = f64::from(q[k]) + f64::from(back.translation[k]);
            assert!((world - p[k]).abs() < 1e-6, "{p:?} vs {q:?}");
        }
    }
    // Written normalised again (in f32): equal up to rounding.
    for (n, m) in normals.iter().zip(&back.normals) {
        assert!((0..3).all(|k| (n[k] - m[k]).abs() < 1e-6), "{n:?} vs {m:?}");
    }
    // The surface faces up: every normal has a positive z and unit length.
    for n in &back.normals {
        assert!(n[2] > 0.0);
        assert!((n.iter().map(|c| c * c).sum::<f32>() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn rgb_and_rgba_colours_read_back() {
    let (positions, indices) = patch([0.0; 3]);
    let normals = vertex_normals(&positions, &indices);
    let rgb: Vec<[u8; 3]> = (0..6).map(|i| [i * 40, 255 - i * 40, 7]).collect();
    let bytes = write_glb(&GlbMesh {
        positions: &positions,
        normals: &normals,
        indices: &indices,
        colors: Some(VertexColors::Rgb(&rgb)),
    })
    .unwrap();
    let back = read_back(&bytes);
    let expected: Vec<[u8; 4]> = rgb.iter().map(|&[r, g, b]| [r, g, b, 255]).collect();
    assert_eq!(back.colors, Some(expected));

    let rgba: Vec<[u8; 4]> = (0..6).map(|i| [i, 2 * i, 3 * i, 200 - i]).collect();
    let bytes = write_glb(&GlbMesh {
        positions: &positions,
        normals: &normals,
        indices: &indices,
        colors: Some(VertexColors::Rgba(&rgba)),
    })
    .unwrap();
    assert_eq!(read_back(&bytes).colors, Some(rgba));
}

#[test]
fn map_coordinates_keep_their_precision_in_the_translation() {
    // UTM-like coordinates: f32 alone would round them to 0.25 m.
    let offset = [2_667_405.25, 6_478_105.75, 120.125];
    let (positions, indices) = patch(offset);
    let normals = vertex_normals(&positions, &indices);
    let bytes = write_glb(&GlbMesh {
        positions: &positions,
        normals: &normals,
        indices: &indices,
        colors: None,
    })
    .unwrap();
    // The JSON chunk holds the translation as a double.
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let document: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let translation: Vec<f64> = document["nodes"][0]["translation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let back = read_back(&bytes);
    for (p, q) in positions.iter().zip(&back.positions) {
        for k in 0..3 {
            assert!((f64::from(q[k]) + translation[k] - p[k]).abs() < 1e-6);
        }
    }
}

#[test]
fn inconsistent_meshes_are_errors() {
    let (positions, indices) = patch([0.0; 3]);
    let normals = vertex_normals(&positions, &indices);
    let mesh = GlbMesh {
        positions: &positions,
        normals: &normals,
        indices: &indices,
        colors: None,
    };
    let short = [[0u8; 3]; 2];
    let cases = [
        (
            GlbMesh {
                normals: &normals[..5],
                ..mesh
            },
            "normals",
        ),
        (
            GlbMesh {
                colors: Some(VertexColors::Rgb(&short)),
                ..mesh
            },
            "colours",
        ),
        (
            GlbMesh {
                indices: &indices[..4],
                ..mesh
            },
            "multiple of 3",
        ),
        (
            GlbMesh {
                indices: &[0, 1, 6],
                ..mesh
            },
            "vertex 6",
        ),
        (
            GlbMesh {
                indices: &[],
                ..mesh
            },
            "no triangles",
        ),
    ];
    for (bad, words) in cases {
        let err = write_glb(&bad).unwrap_err();
        assert!(err.to_string().contains(words), "{err}");
    }
    let mut nan = positions.clone();
    nan[2][1] = f64::NAN;
    let err = write_glb(&GlbMesh {
        positions: &nan,
        ..mesh
    })
    .unwrap_err();
    assert_eq!(
        err,
        GlbError::NotFinite {
            what: "position",
            vertex: 2
        }
    );
}
