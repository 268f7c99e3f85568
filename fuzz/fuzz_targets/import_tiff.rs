//! libFuzzer target: see `paretomesh_fuzz::run` for what is checked.
#![no_main]

use libfuzzer_sys::fuzz_target;
use paretomesh_fuzz::{Target, run};

fuzz_target!(|data: &[u8]| {
    run(Target::Tiff, data);
});
