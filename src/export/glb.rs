//! Binary glTF 2.0 (`.glb`): one triangle mesh with positions, normals, indices and optional
//! vertex colours, the format three.js, Babylon, Cesium and Blender read.
//!
//! The container is small enough to write by hand: a 12-byte header, a JSON chunk and a binary
//! chunk, each padded to 4 bytes. Positions are stored as f32 relative to the centre of their
//! bounding box, which goes into the node's translation (f64 in the JSON): map coordinates such
//! as a GeoTIFF's (millions of metres) would otherwise lose their decimetres to f32 rounding.

use super::mesh::area_normal;
use serde_json::{Value, json};
use std::fmt;

/// Per-vertex colours, 8 bits per channel (linear, as glTF's COLOR_0 is), e.g. an error map.
#[derive(Clone, Copy, Debug)]
pub enum VertexColors<'a> {
    /// Red, green, blue.
    Rgb(&'a [[u8; 3]]),
    /// Red, green, blue, alpha.
    Rgba(&'a [[u8; 4]]),
}

impl VertexColors<'_> {
    fn len(&self) -> usize {
        match self {
            Self::Rgb(c) => c.len(),
            Self::Rgba(c) => c.len(),
        }
    }
}

/// A triangle mesh to write: every slice but `indices` has one entry per vertex.
#[derive(Clone, Copy, Debug)]
pub struct GlbMesh<'a> {
    /// Vertex positions in the mesh's own coordinates.
    pub positions: &'a [[f64; 3]],
    /// Vertex normals; they are normalised on writing (a zero normal becomes +z).
    pub normals: &'a [[f32; 3]],
    /// Triangles as vertex-index triples, counter-clockwise seen from the front.
    pub indices: &'a [u32],
    /// Optional vertex colours.
    pub colors: Option<VertexColors<'a>>,
}

/// Why a mesh could not be written.
#[derive(Clone, Debug, PartialEq)]
pub enum GlbError {
    /// The mesh has no vertices or no triangles.
    Empty,
    /// A per-vertex slice is not as long as `positions`.
    LengthMismatch {
        what: &'static str,
        expected: usize,
        found: usize,
    },
    /// The index count is not a multiple of 3.
    PartialTriangle { indices: usize },
    /// An index points past the last vertex.
    IndexOutOfRange { index: u32, vertices: usize },
    /// A position or normal is NaN or infinite.
    NotFinite { what: &'static str, vertex: usize },
    /// The binary data would not fit a .glb's 32-bit lengths.
    TooLarge,
}

impl fmt::Display for GlbError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "the mesh has no vertices or no triangles to write"),
            Self::LengthMismatch {
                what,
                expected,
                found,
            } => write!(
                f,
                "the mesh has {expected} vertices but {found} {what}; each vertex needs one"
            ),
            Self::PartialTriangle { indices } => write!(
                f,
                "the mesh has {indices} triangle indices, which is not a multiple of 3"
            ),
            Self::IndexOutOfRange { index, vertices } => write!(
                f,
                "a triangle uses vertex {index}, but there are only {vertices} vertices"
            ),
            Self::NotFinite { what, vertex } => write!(
                f,
                "the {what} of vertex {vertex} is not a finite number (NaN or infinity)"
            ),
            Self::TooLarge => write!(f, "the mesh is too large for a .glb file (4 GB)"),
        }
    }
}

impl std::error::Error for GlbError {}

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_BYTE: u32 = 5121;
const UNSIGNED_INT: u32 = 5125;
const TRIANGLES: u32 = 4;

fn check(mesh: &GlbMesh<'_>) -> Result<(), GlbError> {
    let n = mesh.positions.len();
    if n == 0 || mesh.indices.is_empty() {
        return Err(GlbError::Empty);
    }
    let lengths = [
        ("normals", Some(mesh.normals.len())),
        ("colours", mesh.colors.map(|c| c.len())),
    ];
    for (what, len) in lengths {
        if let Some(found) = len.filter(|&l| l != n) {
            return Err(GlbError::LengthMismatch {
                what,
                expected: n,
                found,
            });
        }
    }
    if !mesh.indices.len().is_multiple_of(3) {
        return Err(GlbError::PartialTriangle {
            indices: mesh.indices.len(),
        });
    }
    if let Some(&index) = mesh.indices.iter().find(|&&i| i as usize >= n) {
        return Err(GlbError::IndexOutOfRange { index, vertices: n });
    }
    if let Some(vertex) = mesh
        .positions
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        return Err(GlbError::NotFinite {
            what: "position",
            vertex,
        });
    }
    if let Some(vertex) = mesh
        .normals
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        return Err(GlbError::NotFinite {
            what: "normal",
            vertex,
        });
    }
    Ok(())
}

/// Appends `bytes` to `bin` at a 4-byte boundary and returns its buffer view.
fn push_view(bin: &mut Vec<u8>, bytes: &[u8], target: u32, stride: Option<usize>) -> Value {
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut view = json!({
        "buffer": 0,
        "byteOffset": bin.len(),
        "byteLength": bytes.len(),
        "target": target,
    });
    if let Some(stride) = stride {
        view["byteStride"] = json!(stride);
    }
    bin.extend_from_slice(bytes);
    view
}

/// Writes `mesh` as a binary glTF 2.0 file: one scene, one node, one mesh with one triangle
/// primitive and a double-sided material (a height field is an open surface, seen from both
/// sides). Fails on inconsistent input, never panics.
pub fn write_glb(mesh: &GlbMesh<'_>) -> Result<Vec<u8>, GlbError> {
    check(mesh)?;
    let (centre, local) = centred(mesh.positions);
    let Buffers {
        bin,
        views,
        accessors,
        attributes,
    } = buffers(mesh, &local);
    let mut node = json!({"mesh": 0});
    if centre.iter().any(|&c| c != 0.0) {
        node["translation"] = json!(centre);
    }
    let document = json!({
        "asset": {"version": "2.0", "generator": "ParetoMesh"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [node],
        "meshes": [{"primitives": [{
            "attributes": attributes,
            "indices": 2,
            "material": 0,
            "mode": TRIANGLES,
        }]}],
        "materials": [{
            "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0},
            "doubleSided": true,
        }],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    container(&document, &bin)
}

/// The centre of the positions' bounding box, and the positions relative to it in single
/// precision (the node's translation puts them back).
fn centred(positions: &[[f64; 3]]) -> ([f64; 3], Vec<[f32; 3]>) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let centre: [f64; 3] = std::array::from_fn(|k| (lo[k] + hi[k]) / 2.0);
    let local: Vec<[f32; 3]> = positions
        .iter()
        .map(|p| std::array::from_fn(|k| (p[k] - centre[k]) as f32))
        .collect();
    (centre, local)
}

/// The binary buffer and the glTF views, accessors and attributes that describe it.
struct Buffers {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    attributes: Value,
}

/// The vertex positions (`local`, with their bounds), normals, indices and colours of `mesh`,
/// one buffer view and accessor each, in one buffer padded to 4 bytes.
fn buffers(mesh: &GlbMesh<'_>, local: &[[f32; 3]]) -> Buffers {
    let n = mesh.positions.len();
    let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in local {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    let normals = mesh.normals.iter().map(|v| {
        let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if length > 0.0 && length.is_finite() {
            v.map(|c| c / length)
        } else {
            [0.0, 0.0, 1.0]
        }
    });

    let mut bin = Vec::new();
    let floats = |values: &mut dyn Iterator<Item = [f32; 3]>| -> Vec<u8> {
        values
            .flat_map(|v| v.map(f32::to_le_bytes))
            .flatten()
            .collect()
    };
    let mut views = vec![
        push_view(
            &mut bin,
            &floats(&mut local.iter().copied()),
            ARRAY_BUFFER,
            None,
        ),
        push_view(
            &mut bin,
            &floats(&mut normals.into_iter()),
            ARRAY_BUFFER,
            None,
        ),
        push_view(
            &mut bin,
            &mesh
                .indices
                .iter()
                .flat_map(|i| i.to_le_bytes())
                .collect::<Vec<u8>>(),
            ELEMENT_ARRAY_BUFFER,
            None,
        ),
    ];
    let mut accessors = vec![
        json!({"bufferView": 0, "componentType": FLOAT, "count": n, "type": "VEC3",
               "min": min, "max": max}),
        json!({"bufferView": 1, "componentType": FLOAT, "count": n, "type": "VEC3"}),
        json!({"bufferView": 2, "componentType": UNSIGNED_INT, "count": mesh.indices.len(),
               "type": "SCALAR"}),
    ];
    let mut attributes = json!({"POSITION": 0, "NORMAL": 1});
    if let Some(colors) = mesh.colors {
        // Vertex attributes start on 4-byte boundaries: RGB gets a padding byte per vertex.
        let (bytes, kind, stride): (Vec<u8>, &str, Option<usize>) = match colors {
            VertexColors::Rgb(c) => (
                c.iter().flat_map(|&[r, g, b]| [r, g, b, 0]).collect(),
                "VEC3",
                Some(4),
            ),
            VertexColors::Rgba(c) => (c.iter().flatten().copied().collect(), "VEC4", None),
        };
        views.push(push_view(&mut bin, &bytes, ARRAY_BUFFER, stride));
        accessors.push(json!({"bufferView": 3, "componentType": UNSIGNED_BYTE,
                              "normalized": true, "count": n, "type": kind}));
        attributes["COLOR_0"] = json!(3);
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    Buffers {
        bin,
        views,
        accessors,
        attributes,
    }
}

/// The GLB container: the 12-byte header, the JSON chunk (space-padded) and the binary chunk.
fn container(document: &Value, bin: &[u8]) -> Result<Vec<u8>, GlbError> {
    let mut text = document.to_string().into_bytes();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let total = u32::try_from(total).map_err(|_| GlbError::TooLarge)?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    Ok(out)
}

/// Area-weighted vertex normals of a triangle mesh (each triangle adds its unnormalised cross
/// product to its three corners), normalised; a vertex in no triangle with area gets +z.
/// Indices past the last vertex are skipped.
pub fn vertex_normals(positions: &[[f64; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut sums = vec![[0.0f64; 3]; positions.len()];
    for t in indices.chunks_exact(3) {
        if t.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
        let n = area_normal(a, b, c);
        for &i in t {
            for k in 0..3 {
                sums[i as usize][k] += n[k];
            }
        }
    }
    sums.into_iter()
        .map(|s| {
            let length = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
            if length > 0.0 && length.is_finite() {
                s.map(|c| (c / length) as f32)
            } else {
                [0.0, 0.0, 1.0]
            }
        })
        .collect()
}
