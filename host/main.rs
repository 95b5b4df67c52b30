//! The `vkrt` binary: parses the command line and reports errors with their context.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = vkrt::cli::Cli::parse();
    match vkrt::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
