//! The pixel-coverage reference: the hard visibility averaged over a pixel's footprint, what an
//! anti-aliased image should show, to judge filtered techniques against.
//!
//! For each pixel whose centre sample is evaluated, n×n primary rays go through the centres of an
//! n×n grid of sub-pixel strata (a box filter; fixed centres, no jitter, so a 1×1 grid is the
//! pixel-centre ray and reproduces the hard reference bit for bit). Each sub-ray hits its own
//! surface point, classified as in the G-buffer and shadow-tested exactly like the hard
//! reference. Sub-rays that hit nothing are left out of the mean (the pixel's visibility is that
//! of its surfaces); sub-samples on surfaces facing away from the light or outside a spot
//! light's cone count as shadowed.

use super::gbuffer::{GBuffer, LightSight, PixelClass, surface_sample};
use super::hard::{hard_visible, shadow_ray_to_centre};
use super::sampling::stratum_centre;
use super::soft_reference::{Estimate, SoftReference, trace_evaluated};
use crate::scene::{Camera, Light, Scene};
use crate::trace::bvh::scene_bvh::{SceneBvh, WIDE_BATCH};
use glam::Vec3;

/// Traces the coverage reference on an n×n sub-pixel grid (`grid` = n ≥ 1).
///
/// `gbuffer` must be the G-buffer of (`scene`, `camera`, `light`): it decides which pixels are
/// evaluated. Panics if `grid` is 0 (callers validate user input).
pub fn trace_coverage_reference(
    scene: &Scene,
    bvh: &SceneBvh,
    gbuffer: &GBuffer,
    camera: &Camera,
    light: &Light,
    grid: u32,
) -> SoftReference {
    assert!(grid >= 1, "the coverage grid must be at least 1×1");
    let film = camera.film();
    let sight = LightSight::of(light);
    trace_evaluated(bvh, gbuffer, grid * grid, |scratch, rays, x, y, i| {
        let mut surfaces = 0u32;
        // The sub-rays `WIDE_BATCH` at a time (a pixel's 4×4 at once); their evaluated surfaces'
        // shadow rays join the row's.
        let samples = grid * grid;
        for first in (0..samples).step_by(WIDE_BATCH) {
            let n = (samples - first).min(WIDE_BATCH as u32) as usize;
            let dirs: [Vec3; WIDE_BATCH] = std::array::from_fn(|k| {
                let (sx, sy) = stratum_centre(first + k.min(n - 1) as u32, grid);
                film.direction(x as f64 + sx, y as f64 + sy)
            });
            let mut primary = [None; WIDE_BATCH];
            bvh.closest_hits(scratch, camera.position, &dirs[..n], &mut primary[..n]);
            for (k, hit) in primary[..n].iter().enumerate() {
                let Some(hit) = hit else { continue };
                surfaces += 1;
                let s = surface_sample(hit, dirs[k], &sight);
                if s.class == PixelClass::Evaluated {
                    let ray = shadow_ray_to_centre(&s.point, &sight);
                    rays.push(bvh, scratch, x, ray);
                }
            }
        }
        if surfaces > 0 {
            Estimate::Mean { samples: surfaces }
        } else {
            // Only possible if no sub-ray reproduces the centre hit: fall back to the centre's
            // hard visibility.
            let lit = hard_visible(bvh, scratch, &gbuffer.surface_point(scene, i), &sight);
            Estimate::Known(lit as u32 as f32, 0.0)
        }
    })
}
