//! The library's errors as Python exceptions: [`hull::HullError`] becomes `hullskin.HullskinError`
//! (a `ValueError`, with `file`, `line` and `column` where the error has a place), or an
//! `OSError` for a file that cannot be read or written; the message is the library's own.

use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    hullskin,
    HullskinError,
    PyValueError,
    "An error of the hullskin library: bad offsets (with `file`, `line` and `column` where known), a fit the \
     kernel refuses, a draft out of range, a limit exceeded. A ValueError."
);

/// The Python exception of a library error.
pub fn to_py(e: hull::HullError) -> PyErr {
    let message = e.to_string();
    match &e {
        hull::HullError::Io { error, .. } if error.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(message)
        }
        hull::HullError::Io { .. } => PyOSError::new_err(message),
        hull::HullError::Input { at, .. } => {
            let err = HullskinError::new_err(message);
            Python::attach(|py| {
                let value = err.value(py);
                // Setting attributes on a fresh exception instance cannot fail.
                let _ = value.setattr("file", at.file.clone());
                let _ = value.setattr("line", at.line);
                let _ = value.setattr("column", at.column);
            });
            err
        }
        _ => {
            let err = HullskinError::new_err(message);
            Python::attach(|py| {
                let value = err.value(py);
                let _ = value.setattr("file", py.None());
                let _ = value.setattr("line", py.None());
                let _ = value.setattr("column", py.None());
            });
            err
        }
    }
}

/// A `ValueError` for an argument given from Python.
pub fn bad_arg(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// An `OSError` naming the path that could not be written.
pub fn io_error(path: &std::path::Path, e: &std::io::Error) -> PyErr {
    PyOSError::new_err(format!("cannot write {}: {e}", path.display()))
}
