//! File writers shared by the command line and the browser app: the simplified mesh in the
//! input's own coordinates ([`mesh::WorldMesh`]) as PLY, OBJ, STL, binary glTF or 3MF,
//! closed into a printable solid on request ([`solid`]), and the front as CSV.

pub mod csv;
pub mod glb;
pub mod mesh;
pub mod obj;
pub mod ply;
pub mod solid;
pub mod stl;
pub mod threemf;
pub mod zip_archive;
