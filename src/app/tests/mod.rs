//! The app's logic, tested natively inside the crate: the app is the browser's logic, which
//! only the page (`web`, wasm32) and these tests use, so it is not part of the library's API.
//! Share links are tested beside their codec, in `share/tests.rs`.

mod compare;
mod logic;
mod pool;
mod pyramid_export;
