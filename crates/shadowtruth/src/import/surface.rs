//! Which evaluated pixels of an imported buffer show the reference's surface, and the buffer's
//! visibility on them.

use super::error::{ImportError, Result};
use super::{DEPTH_FLOOR_WORLD, ImportedImage};
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
            return Err(ImportError::File {
                path: image.path.clone(),
                message: format!(
                    "{}×{} pixels, but the view is {}×{}",
                    image.width, image.height, gbuffer.width, gbuffer.height
                ),
            });
        }
    }
    if !(depth_tolerance.is_finite() && depth_tolerance >= 0.0) {
        return Err(ImportError::Invalid(format!(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::PixelFootprint;
    use crate::trace::PixelClass;
    use glam::Vec3;

    /// Two evaluated pixels 5 and 10 units in front of a camera at the origin.
    fn gbuffer() -> (GBuffer, Camera) {
        let camera = Camera {
            name: "c".into(),
            path: None,
            position: Vec3::ZERO,
            look_at: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            width: 2,
            height: 1,
        };
        let g = GBuffer {
            width: 2,
            height: 1,
            class: vec![PixelClass::Evaluated; 2],
            position: vec![Vec3::new(0.0, 3.0, -4.0), Vec3::new(0.0, 0.0, -10.0)],
            barycentric: vec![[0.0; 2]; 2],
            normal: vec![Vec3::Z; 2],
            triangle: vec![0, 1],
            evaluated: vec![0, 1],
            footprint: PixelFootprint::of(&camera),
        };
        (g, camera)
    }

    fn image(values: Vec<f32>) -> ImportedImage {
        ImportedImage { path: "x.exr".into(), width: 2, height: 1, values }
    }

    #[test]
    fn background_and_distant_depths_are_mismatches_at_the_stated_tolerance() {
        let (g, camera) = gbuffer();
        let vis = |values| evaluated_visibility(&g, &camera, &image(values), None, 1e-3).unwrap();
        assert_eq!(vis(vec![1.0, 0.0]), vec![1.0, 0.0]);
        assert!(vis(vec![-1.0, 0.0])[0].is_nan(), "negative: background");
        assert!(vis(vec![1.0, f32::NAN])[1].is_nan(), "NaN: background");
        // Distances 5 and 10: tolerance 1e-3·t + 1e-4 is 0.0051 and 0.0101.
        let with_depth = |d: Vec<f32>| {
            evaluated_visibility(&g, &camera, &image(vec![1.0, 0.0]), Some(&image(d)), 1e-3).unwrap()
        };
        assert_eq!(with_depth(vec![5.005, 9.99]), vec![1.0, 0.0]);
        let v = with_depth(vec![5.006, 10.0102]);
        assert!(v[0].is_nan() && v[1].is_nan());
        let v = with_depth(vec![0.0, f32::INFINITY]);
        assert!(v[0].is_nan() && v[1].is_nan(), "0 and +inf: background");
        let wrong_size = ImportedImage { width: 1, values: vec![1.0], ..image(vec![]) };
        let e = evaluated_visibility(&g, &camera, &wrong_size, None, 1e-3).unwrap_err().to_string();
        assert_eq!(e, "x.exr: 1×1 pixels, but the view is 2×1");
    }
}
