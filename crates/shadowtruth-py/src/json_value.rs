//! Records the library serializes (counts, verifications) handed to Python as plain dicts, with
//! the keys and values the command's JSON files hold.

use pyo3::prelude::*;

/// `value` as the Python object `json.loads` makes of its JSON text.
pub fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    // Through the text, so that every number and key is exactly what the command writes.
    let text =
        serde_json::to_string(value).map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}
