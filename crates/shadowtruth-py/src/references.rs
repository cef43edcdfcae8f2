//! The references of one view as numpy arrays, as `shadowtruth reference` writes them: the hard
//! mask's grey codes (PNG) and the soft references' visibility and standard error (EXR).

use crate::arrays::image_array;
use crate::error::library_error;
use crate::reference_grid::{DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, checked_grid};
use crate::scene::Scene;
use crate::view;
use numpy::PyArray2;
use pyo3::prelude::*;
use shadowtruth::trace::{SoftReference, trace_area_light_reference, trace_coverage_reference};
use shadowtruth::{GBuffer, trace_hard_reference, trace_scored_view};

/// A soft reference as numpy arrays: (visibility, standard error), both float32.
type SoftArrays<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, PyArray2<f32>>);

/// The exact hard shadow mask of `camera` under `light` (default: the scene's first of each).
///
/// Returns a uint8 array of shape (height, width), row 0 at the top, with the grey codes of the
/// PNG that `shadowtruth reference` writes: 255 lit, 0 shadowed, 128 background, 64 facing
/// away from the light, 192 outside the light, 96 uncertain (evaluated, but the reference cannot
/// decide it beyond doubt).
#[pyfunction]
#[pyo3(signature = (scene, camera=None, light=None))]
pub fn hard_reference<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    camera: Option<&str>,
    light: Option<&str>,
) -> PyResult<Bound<'py, PyArray2<u8>>> {
    let scene = scene.get();
    let (camera, light) = (view::camera(&scene.scene, camera)?, view::light(&scene.scene, light)?);
    let codes = py.detach(|| {
        let gbuffer = GBuffer::trace(scene.bvh(), camera, light);
        trace_hard_reference(&scene.scene, scene.bvh(), &gbuffer, light).mask_codes(&gbuffer)
    });
    image_array(py, camera.width, codes)
}

/// The pixel-coverage reference of `camera` under `light`: hard visibility averaged over a
/// grid×grid sub-pixel grid (default 4, at most 64), as `shadowtruth reference --kind coverage`.
///
/// Returns (visibility, std_error): two float32 arrays of shape (height, width), row 0 at the
/// top; visibility in [0, 1] (1 lit), both 0 on pixels that are not evaluated.
#[pyfunction]
#[pyo3(
    signature = (scene, camera=None, light=None, grid=DEFAULT_COVERAGE_GRID as i64),
    text_signature = "(scene, camera=None, light=None, grid=4)"
)]
pub fn coverage_reference<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    camera: Option<&str>,
    light: Option<&str>,
    grid: i64,
) -> PyResult<SoftArrays<'py>> {
    let grid = checked_grid(grid)?;
    let scene = scene.get();
    let (camera, light) = (view::camera(&scene.scene, camera)?, view::light(&scene.scene, light)?);
    let reference = py.detach(|| {
        let (gbuffer, _) = trace_scored_view(&scene.scene, scene.bvh(), camera, light);
        trace_coverage_reference(&scene.scene, scene.bvh(), &gbuffer, camera, light, grid)
    });
    soft_arrays(py, reference)
}

/// The area-light reference of `camera` under `light`: the fraction of grid×grid light samples
/// (default 8, at most 64) each point sees, as `shadowtruth reference --kind area`. The light
/// needs a size (`angular_diameter_deg` for a directional light, `radius` for a spot or point
/// light).
///
/// Returns (visibility, std_error): two float32 arrays of shape (height, width), row 0 at the
/// top; visibility in [0, 1] (1 lit), both 0 on pixels that are not evaluated. Raises
/// `shadowtruth.Error` for a light without a usable size.
#[pyfunction]
#[pyo3(
    signature = (scene, camera=None, light=None, grid=DEFAULT_AREA_LIGHT_GRID as i64),
    text_signature = "(scene, camera=None, light=None, grid=8)"
)]
pub fn area_light_reference<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    camera: Option<&str>,
    light: Option<&str>,
    grid: i64,
) -> PyResult<SoftArrays<'py>> {
    let grid = checked_grid(grid)?;
    let scene = scene.get();
    let (camera, light) = (view::camera(&scene.scene, camera)?, view::light(&scene.scene, light)?);
    // Checked before anything is traced, naming the file as the command does.
    shadowtruth::trace::validate_area_light(light, grid).map_err(|e| {
        let message = shadowtruth::Error::from(e).to_string();
        crate::error::Error::new_err(format!("{}: {message}", scene.scene.source.display()))
    })?;
    let reference = py.detach(|| {
        let (gbuffer, _) = trace_scored_view(&scene.scene, scene.bvh(), camera, light);
        trace_area_light_reference(&scene.scene, scene.bvh(), &gbuffer, light, grid)
    });
    soft_arrays(py, reference.map_err(library_error)?)
}

fn soft_arrays(py: Python<'_>, reference: SoftReference) -> PyResult<SoftArrays<'_>> {
    let width = reference.width;
    Ok((image_array(py, width, reference.visibility)?, image_array(py, width, reference.std_error)?))
}
