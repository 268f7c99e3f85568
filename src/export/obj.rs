//! Wavefront OBJ.

use super::mesh::WorldMesh;
use std::fmt::Write;

/// `mesh` as Wavefront OBJ (1-based face indices); each line of `comment` becomes a `#` line.
pub fn to_obj(mesh: &WorldMesh, comment: &str) -> String {
    let mut s = String::new();
    for line in comment.lines() {
        let _ = writeln!(s, "# {line}");
    }
    for v in &mesh.vertices {
        let _ = writeln!(s, "v {} {} {}", v[0], v[1], v[2]);
    }
    for t in &mesh.triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}
