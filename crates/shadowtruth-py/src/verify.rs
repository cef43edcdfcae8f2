//! `verify`: the hard reference of one view checked against exact predicates, as `shadowtruth
//! verify` checks it (docs/reference.md).

use crate::json_value::to_python;
use crate::scene::Scene;
use crate::view;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use shadowtruth::verify::{Adjudicator, PixelSelection, verify_view};

/// Checks the hard reference of `camera` under `light` (default: the scene's first of each)
/// against the exact answer, as `shadowtruth verify` does.
///
/// `pixels`: "all", or N for about N evaluated pixels spread uniformly plus every pixel next to
/// a shadow boundary (default 100000, the command's).
///
/// Returns a dict, the view's entry of `shadowtruth verify --json`: camera, light, width,
/// height, evaluated, uncertain (pixels the tracer flagged, shadow and primary), checked,
/// checked_at_boundary, agree, disagree_at_boundary, disagree_away_from_boundary,
/// disagree_in_band, disagree_outside_band, in_band (checked pixels the tracer flagged),
/// primary_checked, primary_disagree_in_band, primary_disagree_outside_band,
/// max_point_error_ratio, cases (the first disagreements, each with its kind, "shadow",
/// "primary" or "facing", pixel and triangles) and seconds. The reference is right when
/// disagree_outside_band and primary_disagree_outside_band are 0.
#[pyfunction]
#[pyo3(signature = (scene, camera=None, light=None, pixels=None))]
pub fn verify<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    camera: Option<&str>,
    light: Option<&str>,
    pixels: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let selection = pixel_selection(pixels)?;
    let scene = scene.get();
    let (camera, light) = (view::camera(&scene.scene, camera)?, view::light(&scene.scene, light)?);
    let verification = py.detach(|| {
        let adjudicator = Adjudicator::new(&scene.scene);
        verify_view(&scene.scene, scene.bvh(), &adjudicator, camera, light, selection)
    });
    to_python(py, &verification)
}

/// `pixels` as the command's `--pixels` reads it: "all" or a positive count.
fn pixel_selection(pixels: Option<&Bound<'_, PyAny>>) -> PyResult<PixelSelection> {
    let Some(pixels) = pixels else { return Ok(PixelSelection::default()) };
    let text = match pixels.extract::<String>() {
        Ok(text) => text,
        // An int in Python's own digits; anything else in its repr, which the parse refuses.
        Err(_) => match pixels.extract::<i64>() {
            Ok(n) => n.to_string(),
            Err(_) => pixels.repr()?.to_string(),
        },
    };
    text.parse().map_err(|e| PyValueError::new_err(format!("pixels: {e}")))
}
