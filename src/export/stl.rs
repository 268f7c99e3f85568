//! Binary STL.

use super::mesh::{WorldMesh, area_normal};

/// `mesh` as binary STL: an 80-byte header (`header`, cut or padded with spaces), the triangle
/// count, then per triangle the unit normal and the three corners as little-endian f32.
pub fn to_stl(mesh: &WorldMesh, header: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    let mut head = [b' '; 80];
    let text = header.as_bytes();
    let n = text.len().min(80);
    head[..n].copy_from_slice(&text[..n]);
    // A header starting with "solid" makes some readers take the file for ASCII STL.
    if head.starts_with(b"solid") {
        head[0] = b'S';
    }
    out.extend_from_slice(&head);
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        for p in [unit_normal(a, b, c), a, b, c] {
            for x in p {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    out
}

/// The unit normal of triangle (`a`, `b`, `c`) by the right-hand rule; zero when degenerate.
fn unit_normal(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let n = area_normal(a, b, c);
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 {
        n.map(|x| x / len)
    } else {
        [0.0; 3]
    }
}
