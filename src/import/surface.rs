//! Which evaluated pixels of an imported buffer show the reference's surface, and the buffer's
//! visibility on them.

use super::{DEPTH_FLOOR_WORLD, ImportedImage};
use crate::error::{Error, Result};
use crate::scene::Camera;
use crate::trace::GBuffer;

/// The imported visibility of every evaluated pixel of `gbuffer` (in `gbuffer.evaluated`
/// order), NaN where the pixel is a surface mismatch (module documentation): the renderer drew
/// background, or, with `depth`, its distance differs from the reference's by more than
/// `depth_tolerance · t + DEPTH_FLOOR_WORLD`. `camera` is the G-buffer's. Both images must be
/// the G-buffer's size.
pub fn evaluated_visibility(
    gbuffer: &GBuffer,
    camera: &Camera,
    visibility: &ImportedImage,
    depth: Option<&ImportedImage>,
    depth_tolerance: f64,
) -> Result<Vec<f32>> {
    for image in std::iter::once(visibility).chain(depth) {
        if (image.width, image.height) != (gbuffer.width, gbuffer.height)
            || image.values.len() != gbuffer.pixel_count()
        {
            return Err(Error::Import {
                path: image.path.clone(),
                message: format!(
                    "{}×{} pixels, but the view is {}×{}",
                    image.width, image.height, gbuffer.width, gbuffer.height
                ),
            });
        }
    }
    if !(depth_tolerance.is_finite() && depth_tolerance >= 0.0) {
        return Err(Error::Invalid(format!(
            "depth tolerance {depth_tolerance}: must be a finite number ≥ 0"
        )));
    }
    let eye = camera.position.as_dvec3();
    let same_surface = |i: usize| -> bool {
        let Some(depth) = depth else { return true };
        let d = depth.values[i] as f64;
        if d == 0.0 || d.is_infinite() {
            return false;
        }
        let t = (gbuffer.position[i].as_dvec3() - eye).length();
        (d - t).abs() <= depth_tolerance * t + DEPTH_FLOOR_WORLD
    };
    Ok(gbuffer
        .evaluated
        .iter()
        .map(|&i| {
            let i = i as usize;
            let v = visibility.values[i];
            let background = v.is_nan() || v < 0.0;
            if background || !same_surface(i) { f32::NAN } else { v }
        })
        .collect())
}
