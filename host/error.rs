//! Errors that name what went wrong and where.
//!
//! Library code returns [`anyhow::Result`] with context attached at each layer (file, line, key
//! path, Vulkan operation). The few structured errors a caller may want to match on live here.

use std::fmt;
use std::path::{Path, PathBuf};

/// An error in an input file, located as precisely as the format allows.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    pub file: PathBuf,
    /// Where in the file: `line 12`, `key Lights[1].Position`, ...
    pub location: Option<String>,
    pub message: String,
}

impl InputError {
    pub fn new(file: &Path, location: Option<String>, message: impl Into<String>) -> Self {
        Self { file: file.to_path_buf(), location, message: message.into() }
    }
    pub fn at_line(file: &Path, line: usize, message: impl Into<String>) -> Self {
        Self::new(file, Some(format!("line {line}")), message)
    }
    pub fn at_key(file: &Path, key: &str, message: impl Into<String>) -> Self {
        Self::new(file, Some(format!("key {key}")), message)
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(loc) => write!(f, "{}: {}: {}", self.file.display(), loc, self.message),
            None => write!(f, "{}: {}", self.file.display(), self.message),
        }
    }
}

impl std::error::Error for InputError {}

/// The exit status of a command-line program whose work returned `result`: on error, prints
/// `error: ` and the whole context chain to stderr and fails. Shared by `vkrt` and the tools.
pub fn exit_code(result: anyhow::Result<()>) -> std::process::ExitCode {
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
