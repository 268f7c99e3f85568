//! File writers shared by the command line and the browser app: the simplified mesh in the
//! input's own coordinates ([`WorldMesh`]) as PLY, OBJ, STL, binary glTF or 3MF,
//! closed into a printable solid on request ([`solid()`]), and the front as CSV. One private
//! file per format; what they offer is re-exported here.

mod csv;
mod glb;
mod mesh;
mod obj;
mod ply;
mod solid;
mod stl;
mod threemf;
mod zip_archive;

pub use csv::front_csv;
pub use glb::{GlbError, GlbMesh, VertexColors, vertex_normals, write_glb};
pub use mesh::WorldMesh;
pub use obj::to_obj;
pub use ply::to_ply;
pub use solid::{SolidError, SolidOptions, signed_volume, solid};
pub use stl::to_stl;
pub use threemf::{to_3mf, to_3mf_deflated};

pub(crate) use zip_archive::deflated_zip;
