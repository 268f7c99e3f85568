//! Code shared by the integration tests that run the binary: [`cli`]. The crate's own tests
//! share their grids through `src/evaluator/test_grids.rs`.
#![allow(dead_code)]

pub mod cli;
