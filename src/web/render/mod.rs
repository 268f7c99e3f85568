//! The 3-D view: an orbit camera ([`camera`]), vertex data built on the CPU ([`geometry`]) and
//! the wgpu renderer ([`gpu`]): WebGPU where the browser offers an adapter, WebGL2 otherwise.

pub mod camera;
pub mod geometry;
pub mod gpu;
