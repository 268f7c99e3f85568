//! Writing simplified meshes to the file formats other 3-D tools read.

pub mod glb;
