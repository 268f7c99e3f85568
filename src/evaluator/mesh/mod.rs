//! Meshes of kept grid points: the canonical Delaunay triangulation, its canonical forms, the
//! scored [`MeshState`](state::MeshState), and the ways a part of it is re-triangulated (hole
//! fill after a removal, gift wrapping of a region).

pub(crate) mod canonical_form;
pub(crate) mod canonical_triangulation;
pub(crate) mod disc_box;
pub(crate) mod hole_fill;
pub(crate) mod region;
pub(crate) mod state;
