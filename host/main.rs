//! The `vkrt` binary: parses the command line and reports errors with their context.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = vkrt::cli::Cli::parse();
    vkrt::error::exit_code(vkrt::cli::run(cli))
}
