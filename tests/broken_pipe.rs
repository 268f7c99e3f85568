//! The CLI writing into a pipe whose reader has gone (`paretomesh info F | head -1`) ends
//! quietly: no panic message on stderr. Unix only: that is where SIGPIPE and the CLI are.
#![cfg(unix)]

use std::process::{Command, Stdio};

#[test]
fn info_into_a_closed_pipe_ends_without_a_panic() {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    // The reader is gone before the process starts, so its first write meets a broken pipe.
    drop(reader);
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let output = Command::new(env!("CARGO_BIN_EXE_paretomesh"))
        .arg("info")
        .arg(data.join("jacksboro_65x65.f32"))
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .expect("the paretomesh binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !stderr.contains("panicked") && !stderr.contains("Broken pipe"),
        "stderr: {stderr}"
    );
    // 101 is the exit code of a Rust panic.
    assert_ne!(output.status.code(), Some(101), "stderr: {stderr}");
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(
        output.status.signal(),
        Some(libc::SIGPIPE),
        "ended by SIGPIPE"
    );
}
