//! The sample grids of the soft references, as the `shadowtruth reference` command takes them:
//! N for an N×N grid per pixel.

use pyo3::PyResult;
use pyo3::exceptions::PyValueError;
pub use shadowtruth::trace::{DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, MAX_REFERENCE_GRID};

/// `grid` checked against the command's bounds, with the command's wording.
/// (An `i64`, so that a negative grid is this error rather than an overflow.)
pub fn checked_grid(grid: i64) -> PyResult<u32> {
    if (1..=MAX_REFERENCE_GRID as i64).contains(&grid) {
        return Ok(grid as u32);
    }
    Err(PyValueError::new_err(format!(
        "grid {grid} is outside 1..={MAX_REFERENCE_GRID} (N for an N×N grid per pixel)"
    )))
}
