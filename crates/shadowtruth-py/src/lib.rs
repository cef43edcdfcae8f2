//! The `shadowtruth` Python module: load a scene, trace the references of a view as numpy
//! arrays, verify the hard reference, and score a renderer's visibility buffer, each answer the
//! same as the `shadowtruth` command's (docs/python.md).

use pyo3::prelude::*;

mod arrays;
mod buffer;
mod error;
mod json_value;
mod reference_grid;
mod references;
mod scene;
mod score;
mod verify;
mod view;

/// shadowtruth: how wrong shadow maps are, against an exact ray-traced reference.
///
/// load_scene(path) -> Scene; hard_reference, coverage_reference and area_light_reference of a
/// view as numpy arrays; verify(...) -> dict; score(..., visibility) -> dict. Images are
/// (height, width) arrays, row 0 at the top; cameras and lights by name, None for the first.
#[pymodule]
#[pyo3(name = "shadowtruth")]
fn python_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("Error", m.py().get_type::<error::Error>())?;
    m.add_class::<scene::Scene>()?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(references::hard_reference, m)?)?;
    m.add_function(wrap_pyfunction!(references::coverage_reference, m)?)?;
    m.add_function(wrap_pyfunction!(references::area_light_reference, m)?)?;
    m.add_function(wrap_pyfunction!(verify::verify, m)?)?;
    m.add_function(wrap_pyfunction!(score::score, m)?)?;
    m.add("DEFAULT_COVERAGE_GRID", reference_grid::DEFAULT_COVERAGE_GRID)?;
    m.add("DEFAULT_AREA_LIGHT_GRID", reference_grid::DEFAULT_AREA_LIGHT_GRID)?;
    m.add("MAX_REFERENCE_GRID", reference_grid::MAX_REFERENCE_GRID)?;
    m.add("DEFAULT_DEPTH_TOLERANCE", shadowtruth::import::DEFAULT_DEPTH_TOLERANCE)?;
    m.add("DEFAULT_ATTRIBUTION_RESOLUTION", shadowtruth::metrics::DEFAULT_ATTRIBUTION_RESOLUTION)?;
    m.add("DEFAULT_SAMPLE_PIXELS", shadowtruth::verify::DEFAULT_SAMPLE_PIXELS)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
