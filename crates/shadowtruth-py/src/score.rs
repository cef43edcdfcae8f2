//! `score`: a renderer's visibility buffer of one view (and optionally its camera depth) scored
//! against the exact hard reference, with the same counts and attribution as `shadowtruth
//! score` records in report.json.

use crate::buffer::buffer_image;
use crate::error::library_error;
use crate::json_value::to_python;
use crate::scene::Scene;
use crate::view;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use shadowtruth::import::{BufferKind, DEFAULT_DEPTH_TOLERANCE, evaluated_visibility};
use shadowtruth::metrics::{DEFAULT_ATTRIBUTION_RESOLUTION, LightUv, attribute, score_hard};
use shadowtruth::raster::MAX_SHADOW_MAP_RESOLUTION;
use shadowtruth::trace::trace_shadow_overlap;
use shadowtruth::{Counts, Light, LightView, trace_scored_view};

/// Scores a renderer's shadows of `camera` under `light` (default: the scene's first of each)
/// against the exact hard reference, as `shadowtruth score --visibility` does.
///
/// `visibility`: float32 array of shape (height, width), row 0 at the top, 1 lit and 0
/// shadowed (½ or more counts as lit); NaN or negative where the renderer drew background.
/// `depth` (optional): float32 array of the same shape, the distance from the camera's position
/// to the surface along each primary ray (0 or +inf for background); a pixel whose depth differs
/// from the reference's by more than `depth_tolerance` (relative, plus 1e-4 world units) is a
/// surface mismatch. `resolution`: the shadow-map resolution whose texel footprint the
/// attribution (aliasing) is taken at.
///
/// Returns a dict with the counts of report.json's run — pixels, background, facing_away,
/// outside_light, evaluated, uncertain (pixels the reference cannot decide beyond doubt, scored
/// neither way), false_shadow, false_lit, aliasing, acne, leak, surface_mismatch —
/// and "rates": {false_shadow, false_lit, error}, fractions of the scored pixels (evaluated less
/// surface mismatches). Raises ValueError for an array of the wrong type, dtype or shape, or a
/// value out of range.
#[pyfunction]
#[pyo3(signature = (
    scene, camera, light, visibility, depth=None, depth_tolerance=DEFAULT_DEPTH_TOLERANCE,
    resolution=DEFAULT_ATTRIBUTION_RESOLUTION as i64
), text_signature = "(scene, camera, light, visibility, depth=None, depth_tolerance=1e-3, resolution=2048)")]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments, one per option of the command.
pub fn score<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    camera: Option<&str>,
    light: Option<&str>,
    visibility: &Bound<'py, PyAny>,
    depth: Option<&Bound<'py, PyAny>>,
    depth_tolerance: f64,
    resolution: i64,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = scene.get();
    let (camera, light) = (view::camera(&scene.scene, camera)?, view::light(&scene.scene, light)?);
    let view = attribution_view(&scene.scene, light, resolution)?;
    let size = (camera.width, camera.height);
    let visibility = buffer_image(BufferKind::Visibility, visibility, size)?;
    let depth = depth.map(|d| buffer_image(BufferKind::Depth, d, size)).transpose()?;
    let counts = py.detach(|| -> shadowtruth::Result<Counts> {
        let (gbuffer, reference) = trace_scored_view(&scene.scene, scene.bvh(), camera, light);
        let evaluated = evaluated_visibility(&gbuffer, camera, &visibility, depth.as_ref(), depth_tolerance)?;
        // Where occluders overlap, as the command traces it for the same view.
        let overlap =
            trace_shadow_overlap(&scene.scene, scene.bvh(), &gbuffer, light, |i| reference.lit[i] == 0);
        let uv = LightUv::new(&gbuffer, &view);
        let attribution = attribute(&scene.scene, &gbuffer, &reference, &evaluated, &uv, Some(&overlap));
        Ok(score_hard(&gbuffer, &reference, &evaluated).with_attribution(attribution))
    });
    score_dict(py, &counts.map_err(library_error)?)
}

/// The shadow map of `light` whose texel footprint the attribution uses. A light with cascades
/// or a point light is refused: its footprint is its cascades' or faces', which the command
/// builds per camera.
fn attribution_view(scene: &shadowtruth::Scene, light: &Light, resolution: i64) -> PyResult<LightView> {
    let several = if light.cascades.is_some() {
        Some("has cascades")
    } else if light.is_point() {
        Some("is a point light, with a map of several faces")
    } else {
        None
    };
    if let Some(what) = several {
        return Err(PyValueError::new_err(format!(
            "{}: light {} {what}, whose attribution only `shadowtruth score` computes",
            scene.source.display(),
            light.name
        )));
    }
    // Beyond u32 is refused in the library's words, as every other resolution out of range.
    let resolution = u32::try_from(resolution).map_err(|_| {
        PyValueError::new_err(format!(
            "shadow-map resolution {resolution}: must be between 1 and {MAX_SHADOW_MAP_RESOLUTION}"
        ))
    })?;
    shadowtruth::light_view(scene, light, resolution).map_err(library_error)
}

/// The counts (every field, surface_mismatch too) and their rates.
fn score_dict<'py>(py: Python<'py>, counts: &Counts) -> PyResult<Bound<'py, PyAny>> {
    let dict = to_python(py, counts)?.cast_into::<PyDict>()?;
    // report.json leaves a zero surface_mismatch out; a dict always has it.
    dict.set_item("surface_mismatch", counts.surface_mismatch)?;
    dict.set_item("rates", to_python(py, &counts.rates())?)?;
    Ok(dict.into_any())
}
