//! The `vkrt` binary: parses the command line and reports errors with their context.

use clap::error::ErrorKind;
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    restore_default_sigpipe();
    let args: Vec<String> = std::env::args().collect();
    if args.get(1).map(String::as_str) == Some("render") && args.iter().any(|a| a == vkrt::cli::HELP_EXPERT) {
        println!("{}", vkrt::cli::render_help_expert());
        return ExitCode::SUCCESS;
    }
    let cli = match vkrt::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match e.kind() {
            ErrorKind::DisplayHelp | ErrorKind::DisplayVersion | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
            // A bad flag or value is an error like any other: the message (without clap's usage
            // reminder), exit status 1.
            _ => {
                let text = e.to_string();
                let message: Vec<&str> =
                    text.lines().take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information")).filter(|l| !l.trim().is_empty()).collect();
                eprintln!("{}", message.join("\n"));
                return ExitCode::FAILURE;
            }
        },
    };
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
