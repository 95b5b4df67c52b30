//! vkrt's errors as Python exceptions, with the command line's message: a missing file is a
//! `FileNotFoundError`, a device failure a `RuntimeError`, anything else the input's fault, a
//! `ValueError`.

use pyo3::exceptions::{PyFileNotFoundError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

/// The exception for a failed vkrt call; its text is what `vkrt` would print after "error: ".
pub fn to_py(e: anyhow::Error) -> PyErr {
    let message = format!("{e:#}");
    for cause in e.chain() {
        if let Some(io) = cause.downcast_ref::<std::io::Error>() {
            if io.kind() == std::io::ErrorKind::NotFound {
                return PyFileNotFoundError::new_err(message);
            }
        }
        // Loaders report a file they could not read as an input error naming it.
        if cause.downcast_ref::<vkrt::error::InputError>().is_some_and(|i| !i.file.as_os_str().is_empty() && std::fs::metadata(&i.file).is_err()) {
            return PyFileNotFoundError::new_err(message);
        }
        if cause.downcast_ref::<ash::vk::Result>().is_some() {
            return PyRuntimeError::new_err(message);
        }
    }
    PyValueError::new_err(message)
}

/// `Result` of anything vkrt returns, as a Python result.
pub trait IntoPy<T> {
    fn py_err(self) -> pyo3::PyResult<T>;
}

impl<T> IntoPy<T> for anyhow::Result<T> {
    fn py_err(self) -> pyo3::PyResult<T> {
        self.map_err(to_py)
    }
}
