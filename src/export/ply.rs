//! ASCII PLY.

use super::mesh::WorldMesh;
use std::fmt::Write;

/// `mesh` as ASCII PLY with double-precision vertices and triangle faces; each line of
/// `comment` becomes a `comment` header line.
pub fn to_ply(mesh: &WorldMesh, comment: &str) -> String {
    let mut s = String::new();
    s.push_str("ply\nformat ascii 1.0\n");
    for line in comment.lines() {
        let _ = writeln!(s, "comment {line}");
    }
    let _ = writeln!(s, "element vertex {}", mesh.vertices.len());
    s.push_str("property double x\nproperty double y\nproperty double z\n");
    let _ = writeln!(s, "element face {}", mesh.triangles.len());
    s.push_str("property list uchar int vertex_indices\nend_header\n");
    for v in &mesh.vertices {
        let _ = writeln!(s, "{} {} {}", v[0], v[1], v[2]);
    }
    for t in &mesh.triangles {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    s
}
