//! Helpers of the tests that run the `paretomesh` binary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `tests/data/{name}`.
pub fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Runs the binary `cargo test` built with `args`, from the crate's folder.
pub fn paretomesh(args: &[&str]) -> Output {
    paretomesh_in(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// Runs the binary with `args` from the folder `dir`.
pub fn paretomesh_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_paretomesh"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the paretomesh binary runs")
}

/// A scratch folder of this test binary's process (named after the test file, so test files
/// that run at once never share one).
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "paretomesh-{}-{}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Output bytes as text, for messages.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
