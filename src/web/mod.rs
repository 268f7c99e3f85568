//! The browser layer (wasm32 only): the page over [`crate::app`]. `index.html` and
//! `www/main.js` boot it; the JS only wires the file drop and the `requestAnimationFrame` loop.
//!
//! - [`bindings`]: every function and type the JS calls (`#[wasm_bindgen]`).
//! - [`ui`]: start-up, the frame, loading, exports and the main listeners.
//! - [`share_view`], [`teaching_view`], [`compare_view`], [`oax_panel`]: the panels.
//! - [`page`]: the page state every view works on.
//! - [`dom`]: the page's controls; [`plot_view`]: the plot's drawing; [`preview`]: the import
//!   preview; [`transfer`]: height fields to and from the Worker.
//! - [`pool`]: pool runs' jobs, the worker's runner and its fronts at the JS boundary;
//!   [`mesh_worker`]: tiled members' meshes built in a worker; [`costs`]: main-thread time
//!   per step.
//! - [`gpu`]: the 3-D view: WebGPU through wgpu where the browser offers an adapter, else
//!   WebGL2 ([`webgl`], on web-sys).

pub mod bindings;
mod compare_view;
mod costs;
mod dom;
mod gpu;
mod mesh_worker;
mod oax_panel;
mod page;
mod plot_view;
mod pool;
mod preview;
mod share_view;
mod style;
mod teaching_view;
mod transfer;
mod ui;
mod webgl;

pub use bindings::{WebApp, evaluate_raw};
// The mesh worker's #[wasm_bindgen] type, public like every type the JS calls.
pub use mesh_worker::MeshGrid;
