//! Exports: the selected mesh as PLY, OBJ or STL in the input's own coordinates (through
//! [`Heightfield::to_world`], so a planar or cylindrical unwrap maps back to 3-D), and the front
//! as CSV.

use crate::front::Front;
use crate::heightfield::Heightfield;
use std::fmt::Write;

/// A simplified mesh in world coordinates: the kept points and the triangles over them.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldMesh {
    /// Vertex positions in the input's coordinates, in the order of the kept grid indices.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

impl WorldMesh {
    /// The mesh of `kept` (increasing grid indices that include every triangle corner) and its
    /// grid-index `triangles`. Fails when a triangle uses a point that is not in `kept`.
    pub fn new(hf: &Heightfield, kept: &[u32], triangles: &[[u32; 3]]) -> Result<Self, String> {
        let vertices = kept
            .iter()
            .map(|&i| hf.to_world(i, hf.z()[i as usize]))
            .collect();
        let local = |g: u32| {
            kept.binary_search(&g)
                .map(|k| k as u32)
                .map_err(|_| format!("triangle vertex {g} is not a kept point"))
        };
        let triangles = triangles
            .iter()
            .map(|t| Ok([local(t[0])?, local(t[1])?, local(t[2])?]))
            .collect::<Result<_, String>>()?;
        Ok(Self {
            vertices,
            triangles,
        })
    }

    /// ASCII PLY with double-precision vertices and triangle faces.
    pub fn to_ply(&self, comment: &str) -> String {
        let mut s = String::new();
        s.push_str("ply\nformat ascii 1.0\n");
        for line in comment.lines() {
            let _ = writeln!(s, "comment {line}");
        }
        let _ = writeln!(s, "element vertex {}", self.vertices.len());
        s.push_str("property double x\nproperty double y\nproperty double z\n");
        let _ = writeln!(s, "element face {}", self.triangles.len());
        s.push_str("property list uchar int vertex_indices\nend_header\n");
        for v in &self.vertices {
            let _ = writeln!(s, "{} {} {}", v[0], v[1], v[2]);
        }
        for t in &self.triangles {
            let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
        }
        s
    }

    /// Wavefront OBJ (1-based face indices).
    pub fn to_obj(&self, comment: &str) -> String {
        let mut s = String::new();
        for line in comment.lines() {
            let _ = writeln!(s, "# {line}");
        }
        for v in &self.vertices {
            let _ = writeln!(s, "v {} {} {}", v[0], v[1], v[2]);
        }
        for t in &self.triangles {
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    }

    /// Binary STL: 80-byte header, triangle count, then per triangle the unit normal and the
    /// three corners as little-endian f32.
    pub fn to_stl(&self, header: &str) -> Vec<u8> {
        let mut out = Vec::with_capacity(84 + 50 * self.triangles.len());
        let mut head = [b' '; 80];
        let text = header.as_bytes();
        let n = text.len().min(80);
        head[..n].copy_from_slice(&text[..n]);
        // A header starting with "solid" makes some readers take the file for ASCII STL.
        if head.starts_with(b"solid") {
            head[0] = b'S';
        }
        out.extend_from_slice(&head);
        out.extend_from_slice(&(self.triangles.len() as u32).to_le_bytes());
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i as usize]);
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let n = if len > 0.0 {
                n.map(|x| x / len)
            } else {
                [0.0; 3]
            };
            for p in [n, a, b, c] {
                for x in p {
                    out.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            out.extend_from_slice(&0u16.to_le_bytes());
        }
        out
    }
}

/// The front as CSV: one row per member by increasing T, with the kept count.
pub fn front_csv(front: &Front) -> String {
    let mut s = String::from("T,E_sum,E_max,kept\n");
    for m in front.solutions() {
        let _ = writeln!(s, "{},{},{},{}", m.t, m.e_sum, m.e_max, m.kept.len());
    }
    s
}
