//! The `vkrt` binary: parses the command line and reports errors with their context.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    restore_default_sigpipe();
    let cli = vkrt::cli::Cli::parse();
    vkrt::error::exit_code(vkrt::cli::run(cli))
}

/// Rust starts programs with SIGPIPE ignored, so printing into a closed pipe
/// (`vkrt compare A B | head -1`) makes `println!` panic. With the default action vkrt ends
/// quietly there, as other Unix tools do. Outputs are files written through a temporary and a
/// rename, so no image or checkpoint is left half-written by it.
#[cfg(unix)]
fn restore_default_sigpipe() {
    // SAFETY: the first thing main does, before any thread exists; SIG_DFL is a valid action.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn restore_default_sigpipe() {}
