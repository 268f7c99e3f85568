//! `paretomesh`: the command-line interface to the core, for batch experiments and benchmarks.
//! Native only: in a browser the library is the app (`web`), so for wasm32 this is empty.

#[cfg(not(target_arch = "wasm32"))]
mod cli;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    use clap::Parser;
    restore_sigpipe();
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Restores the default action of SIGPIPE, which Rust's runtime ignores: a write to a closed
/// pipe (`paretomesh info F | head -1`) then ends the process quietly, as for other Unix tools,
/// rather than making `println!` panic on the broken pipe.
#[cfg(all(unix, not(target_arch = "wasm32")))]
fn restore_sigpipe() {
    // SAFETY: called first thing in `main`, before any other thread exists; SIG_DFL is a valid
    // handler for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(any(unix, target_arch = "wasm32")))]
fn restore_sigpipe() {}

#[cfg(target_arch = "wasm32")]
fn main() {}
