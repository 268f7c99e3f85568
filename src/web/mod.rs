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
pub mod compare_view;
pub mod costs;
pub mod dom;
pub mod gpu;
pub mod mesh_worker;
pub mod oax_panel;
pub mod page;
pub mod plot_view;
pub mod pool;
pub mod preview;
pub mod share_view;
pub mod style;
pub mod teaching_view;
pub mod transfer;
pub mod ui;
pub mod webgl;

pub use bindings::{WebApp, evaluate_raw};
