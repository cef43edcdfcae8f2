//! The library's errors as one Python exception, `shadowtruth.Error` (a `ValueError`), carrying
//! the library's message: the file, and the JSON path or pixel at fault.

use pyo3::PyErr;
use pyo3::exceptions::PyValueError;

pyo3::create_exception!(
    shadowtruth,
    Error,
    PyValueError,
    "A scene, light or buffer the library refuses; the message names the file and the JSON path or pixel."
);

/// `error` as a `shadowtruth.Error`, its message the library's.
pub fn library_error(error: impl Into<shadowtruth::Error>) -> PyErr {
    Error::new_err(error.into().to_string())
}
